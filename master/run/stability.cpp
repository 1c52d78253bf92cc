#include "run/stability.hpp"

#include <algorithm>
#include <cmath>

#include <sstream>
#include <stdexcept>

#include "connection.hpp"
#include "log.hpp"

#include "run/evaluation.hpp"
#include "run/matrix_free.hpp"
#include "run/run_output.hpp"
#include "run/spectral.hpp"

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
  // Whole slow windows (multirate).
  const double window =
      options.macro_step * static_cast<double>(rate_plan(scene, spec, options).ratio);
  const Scene parked = parked_scene(scene, window);
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

double unstable_rate(double t_end) {
  return 1.0 / (kGrowthHorizon * t_end);
}

std::vector<double> coupling_defect(const RunRecord& run) {
  const std::size_t n = run.history.size();
  std::vector<double> d(n, 0.0);
  auto add = [&](auto value_at) {
    double scale = 0;
    for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(value_at(i)));
    if (!(scale > 0) || !std::isfinite(scale)) return;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double r = std::abs(value_at(i + 1) - 2 * value_at(i) + value_at(i - 1)) / scale;
      d[i] = std::isfinite(r) ? std::max(d[i], r) : HUGE_VAL;
    }
  };
  add([&](std::size_t i) { return run.history[i].wheel; });
  add([&](std::size_t i) { return run.history[i].contact_force; });
  const std::size_t extra = n > 0 ? run.history[0].extra.size() : 0;
  for (std::size_t k = 0; k < extra; ++k)
    add([&](std::size_t i) {
      return k < run.history[i].extra.size() ? run.history[i].extra[k] : 0.0;
    });
  for (const auto& entry : run.coupling_history) {
    const auto& values = entry.second;  // a lambda captures no structured binding in C++20
    if (values.size() >= n) add([&values](std::size_t i) { return values[i]; });
  }
  return d;
}

DefectGrowth defect_growth(const std::vector<double>& defect, double dt) {
  DefectGrowth g;
  const std::size_t n = defect.size();
  if (n < 16) return g;
  auto largest = [&](std::size_t from, std::size_t to) {
    double m = 0;
    for (std::size_t i = from; i < to; ++i) m = std::max(m, defect[i]);
    return m;
  };
  const std::size_t e = n / 8;
  const double before = largest(2 * e, n - e), last = largest(n - e, n);
  if (!(before > 0)) return g;
  g.growth = last / before;
  // Over one eighth: the spacing of the two largest values of a growing
  // exponential (the ends of the two spans).
  g.rate_per_s = std::log(std::max(g.growth, 1e-300)) / (static_cast<double>(e) * dt);
  g.grows = !(g.growth < kDefectGrowth);
  return g;
}

namespace {

// The measure's budget for a run: Arnoldi's products (each two parked macro
// steps) at most options.judge.budget times half the run's macro steps, and
// at least kJudgeMinProducts; a count, not a time, so that the verdict does
// not depend on the machine's load. The dense map of a model of at most
// kDenseMapLimit coordinates is taken whole. The run's stop flag (and the
// signal that interrupts a wait) is asked before every product.
verdict::Budget judge_budget(const RunRecord& run, const RunOptions& options) {
  verdict::Budget b;
  if (options.judge.budget > 0)
    b.max_products =
        std::max(kJudgeMinProducts,
                 std::lround(options.judge.budget * static_cast<double>(run.macro_steps) / 2));
  const std::atomic<int>* stop = options.stop;
  b.stop = [stop] { return (stop && stop->load() != 0) || interrupt_signal() != 0; };
  return b;
}

// The map's verdict, or the probe's where the map's steps cannot be
// iterated to convergence (implicit coupling); "not judged" with the
// reason where the measure does not converge within its budget.
void judge_growth(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                  const RunOptions& options) {
  MapSettings settings;
  settings.budget = judge_budget(run, options);
  MapSpectrum m;
  logger("master")->info("{}: judging its stability: the macro-step map at rest", run.case_name);
  try {
    m = macro_step_spectrum(scene, spec, options, settings);
  } catch (const verdict::Stopped&) {
    std::ostringstream s;
    s << "interrupted by signal "
      << (options.stop && options.stop->load() ? options.stop->load() : interrupt_signal())
      << " during the stability judgement of " << run.case_name;
    throw std::runtime_error(s.str());
  }
  run.map_method = m.method;
  if (m.products > 0) run.map_products = m.products;
  if (m.dimension > 0) run.map_dimension = m.dimension;
  if (m.computed && m.method == "krylov" && m.rate_per_s < unstable_rate(scene.end_time)) {
    // Arnoldi's converged eigenvalues are eigenvalues, not always the
    // largest (spectral.hpp): a growing one proves instability, the lack of
    // one proves nothing.
    std::ostringstream w;
    w << "the map's " << m.states << " coordinates are more than the dense measure's "
      << kDenseMapLimit
      << ", and the largest eigenvalue Arnoldi's method converged to (ρ = " << rho_words(m.rho)
      << " after " << m.products
      << " products) is below the bound, which does not prove that none is above it";
    run.spectral_note = w.str();
    run.map_seconds = m.seconds;
    run.stability = kNotJudged;
    run.stability_basis = "map";
    return;
  }
  if (m.computed) {
    run.stability_basis = "map";
    run.spectral_radius = m.rho;
    run.spectral_rate = m.rate_per_s;
    run.map_dimension = m.dimension;
    run.map_seconds = m.seconds;
    run.map_micro_steps = m.micro_steps;
    run.stability = m.rate_per_s >= unstable_rate(scene.end_time) ? "unstable" : "stable";
    return;
  }
  run.spectral_note = m.why_not;
  run.map_seconds = m.seconds;
  if (options.coupling.method != engine::CouplingMethod::kImplicit ||
      m.why_not.find("implicit step did not converge") == std::string::npos) {
    // Out of budget: nothing measured is claimed.
    run.stability = kNotJudged;
    run.stability_basis = "map";
    return;
  }
  const Stability s = probe_stability(scene, spec, options);
  run.stability_basis = "probe";
  run.stability = s.unstable ? "unstable" : "stable";
  run.error_growth = s.growth;
  run.error_growth_rate = s.rate_per_s;
  run.probe_time = s.duration_s;
  // Implicit coupling has no map here: its rho through the participants.
  judge_growth_matrix_free(run, scene, spec, options, remote::kInprocTransport, {});
}

}  // namespace

void assess_growth(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                   const RunOptions& options, bool probe) {
  if (run.status != "failed") {
    // A node the user started may run a model of its own behind the
    // scene's name: the map and the probe, built from the scene, would judge
    // the built-in model instead. The defect along the run is its own.
    if (probe)
      judge_growth(run, scene, spec, options);
    else if (run.stability.empty())  // else measured without the map (matrix_free.hpp)
      run.stability = kNotJudged;
    const DefectGrowth d = defect_growth(coupling_defect(run), options.macro_step);
    run.defect_growth = d.growth;
    run.defect_rate = d.rate_per_s;
    run.defect_grows = d.grows;
    if (d.grows) run.stability = "unstable";
  }
}

void assess(RunRecord& run, const RunRecord& reference, const Scene& scene, const CaseSpec& spec,
            const RunOptions& options, bool probe) {
  assess_growth(run, scene, spec, options, probe);
  judge(run, reference, scene);
}

std::string stability_json(const RunRecord& r) {
  std::ostringstream s;
  auto opt = [](const std::optional<double>& v) { return v ? format_double(*v) : "null"; };
  s << "\"stability\": {\"verdict\": " << json_quoted(r.stability)
    << ", \"basis\": " << json_quoted(r.stability_basis) << ", \"rho\": " << opt(r.spectral_radius)
    << ", \"rho_rate_per_s\": " << opt(r.spectral_rate)
    << ", \"map_dimension\": " << (r.map_dimension ? std::to_string(*r.map_dimension) : "null")
    << ", \"map_s\": " << opt(r.map_seconds)
    << ", \"map_method\": " << (r.map_method.empty() ? "null" : json_quoted(r.map_method))
    << ", \"map_products\": " << (r.map_products ? std::to_string(*r.map_products) : "null");
  if (!r.spectral_note.empty()) s << ", \"rho_not_judged\": " << json_quoted(r.spectral_note);
  if (r.matrix_free_steps)
    s << ", \"rho_matrix_free\": " << opt(r.matrix_free_rho)
      << ", \"rho_matrix_free_rate_per_s\": " << opt(r.matrix_free_rate)
      << ", \"matrix_free_steps\": " << *r.matrix_free_steps;
  s << ", \"growth\": " << opt(r.error_growth) << ", \"rate_per_s\": " << opt(r.error_growth_rate)
    << ", \"probe_s\": " << opt(r.probe_time) << ", \"defect_growth\": " << opt(r.defect_growth)
    << ", \"defect_rate_per_s\": " << opt(r.defect_rate)
    << ", \"defect_grows\": " << (r.defect_grows ? "true" : "false") << "}";
  return s.str();
}

}  // namespace railcosim::run
