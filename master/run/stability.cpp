#include "run/stability.hpp"

#include <algorithm>
#include <cmath>

#include "run/evaluation.hpp"

namespace railcosim::run {

Stability classify_growth(const std::vector<double>& deviation, double dt, double floor) {
  Stability s;
  const auto n = static_cast<long>(deviation.size());
  s.steps = n > 0 ? n - 1 : 0;
  s.duration_s = static_cast<double>(s.steps) * dt;
  if (n < 4) return s;
  const long q = n / 4;
  double first = 0, last = 0;
  for (long i = 0; i < q; ++i) first = std::max(first, deviation[static_cast<std::size_t>(i)]);
  for (long i = n - q; i < n; ++i) {
    const double d = deviation[static_cast<std::size_t>(i)];
    last = std::isfinite(d) ? std::max(last, d) : HUGE_VAL;
  }
  s.growth = last / std::max(first, floor);
  s.rate_per_s = std::log(std::max(s.growth, 1e-300)) / (static_cast<double>(n - q) * dt);
  s.unstable = !(s.growth <= kUnstableGrowth);
  return s;
}

namespace {

void track(std::vector<double>& d, const std::vector<double>& series) {
  if (series.empty() || series[0] == 0) return;  // nothing to measure against
  const double scale = std::abs(series[0]);
  for (std::size_t i = 0; i < series.size() && i < d.size(); ++i) {
    const double r = std::abs(series[i] - series[0]) / scale;
    d[i] = std::isfinite(r) ? std::max(d[i], r) : HUGE_VAL;
  }
}

}  // namespace

std::vector<double> deviation_from_rest(const RunRecord& run) {
  const std::size_t n = run.history.size();
  std::vector<double> d(n, 0.0);
  std::vector<double> series(n);
  for (std::size_t i = 0; i < n; ++i) series[i] = run.history[i].wheel;
  track(d, series);
  for (std::size_t i = 0; i < n; ++i) series[i] = run.history[i].contact_force;
  track(d, series);
  const std::size_t extra = n > 0 ? run.history[0].extra.size() : 0;
  for (std::size_t k = 0; k < extra; ++k) {
    for (std::size_t i = 0; i < n; ++i)
      series[i] = k < run.history[i].extra.size() ? run.history[i].extra[k] : series[0];
    track(d, series);
  }
  for (const auto& [cut, values] : run.coupling_history) track(d, values);
  return d;
}

// Run in process only: its fields are changed behind its text, which the
// master would refuse to send to a node (check_scene_text).
Scene parked_scene(const Scene& scene, double macro_step) {
  Scene s = scene;
  s.speed = 0;
  const long wanted = std::max(kProbeMinSteps, std::lround(std::ceil(kProbeTime / macro_step)));
  const long most = std::max(1L, std::lround(scene.end_time / macro_step));
  s.end_time = static_cast<double>(std::min(wanted, most)) * macro_step;
  return s;
}

Stability probe_stability(const Scene& scene, const CaseSpec& spec, const RunOptions& options) {
  const Scene parked = parked_scene(scene, options.macro_step);
  RunOptions o = options;
  o.on_row = nullptr;
  o.on_channels = nullptr;
  o.on_progress = nullptr;
  const RunRecord r =
      run_cosim(parked, spec, o, remote::inproc_factory(parked), remote::kInprocTransport);
  const double floor = options.coupling.method == engine::CouplingMethod::kImplicit
                           ? std::max(kProbeFloor, options.coupling.convergence)
                           : kProbeFloor;
  Stability s = classify_growth(deviation_from_rest(r), options.macro_step, floor);
  if (r.status == "diverged") s.unstable = true;
  return s;
}

void assess(RunRecord& run, const RunRecord& reference, const Scene& scene, const CaseSpec& spec,
            const RunOptions& options, bool probe) {
  if (run.status != "failed" && !probe) {
    run.stability = kNotJudged;
  } else if (run.status != "failed") {
    const Stability s = probe_stability(scene, spec, options);
    run.stability = s.unstable ? "unstable" : "stable";
    run.error_growth = s.growth;
    run.error_growth_rate = s.rate_per_s;
    run.probe_time = s.duration_s;
  }
  judge(run, reference, scene);
}

}  // namespace railcosim::run
