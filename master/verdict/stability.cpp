#include "verdict/stability.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "verdict/evaluation.hpp"

namespace railcosim::verdict {

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

Stability probe_growth(const RunRecord& parked, double dt, bool implicit, double convergence) {
  const double floor = implicit ? std::max(kProbeFloor, convergence) : kProbeFloor;
  Stability s = classify_growth(deviation_from_rest(parked), dt, floor);
  if (parked.status == "diverged") s.unstable = true;
  return s;
}

bool judge_by_map(RunRecord& run, const MapSpectrum& m, double t_end, bool implicit) {
  run.map_method = m.method;
  run.map_solver = m.solver;
  if (m.products > 0) run.map_products = m.products;
  if (m.dimension > 0) run.map_dimension = m.dimension;
  if (m.computed && m.method == "krylov" && m.rate_per_s < unstable_rate(t_end)) {
    // Arnoldi's converged eigenvalues are eigenvalues, not always the
    // largest (spectrum.hpp): a growing one proves instability, the lack of
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
    return false;
  }
  if (m.computed) {
    run.stability_basis = "map";
    run.spectral_radius = m.rho;
    run.spectral_rate = m.rate_per_s;
    run.map_dimension = m.dimension;
    run.map_seconds = m.seconds;
    run.map_micro_steps = m.micro_steps;
    run.stability = m.rate_per_s >= unstable_rate(t_end) ? "unstable" : "stable";
    return false;
  }
  run.spectral_note = m.why_not;
  run.map_seconds = m.seconds;
  if (!implicit || m.why_not.find("implicit step did not converge") == std::string::npos) {
    // Out of budget: nothing measured is claimed.
    run.stability = kNotJudged;
    run.stability_basis = "map";
    return false;
  }
  return true;
}

void judge_by_probe(RunRecord& run, const Stability& s) {
  run.stability_basis = "probe";
  run.stability = s.unstable ? "unstable" : "stable";
  run.error_growth = s.growth;
  run.error_growth_rate = s.rate_per_s;
  run.probe_time = s.duration_s;
}

void judge_defect(RunRecord& run, double dt) {
  const DefectGrowth d = defect_growth(coupling_defect(run), dt);
  run.defect_growth = d.growth;
  run.defect_rate = d.rate_per_s;
  run.defect_grows = d.grows;
  if (d.grows) run.stability = "unstable";
}

void judge_without_model(RunRecord& run, double dt) {
  if (run.status == "failed") return;
  if (run.stability.empty()) run.stability = kNotJudged;
  judge_defect(run, dt);
}

}  // namespace railcosim::verdict
