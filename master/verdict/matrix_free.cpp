#include "verdict/matrix_free.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "verdict/stability.hpp"

namespace railcosim::verdict {
namespace {

using Kind = CouplingPasses::Kind;

// The perturbation of each coordinate: `size` times the largest
// displacement (force) at rest; a velocity as a displacement over H.
std::vector<double> perturbation_sizes(const CouplingPasses& c, double H, double size) {
  double u = 0, f = 0;
  for (std::size_t i = 0; i < c.rest.size(); ++i) {
    if (c.kinds[i] == Kind::kDisplacement) u = std::max(u, std::abs(c.rest[i]));
    if (c.kinds[i] == Kind::kForce) f = std::max(f, std::abs(c.rest[i]));
  }
  const double du = size * (u > 0 ? u : 1e-3);
  const double df = size * (f > 0 ? f : 1e5);
  std::vector<double> e;
  for (Kind kind : c.kinds)
    e.push_back(kind == Kind::kDisplacement ? du : kind == Kind::kVelocity ? du / H : df);
  return e;
}

// The coupling data at rest with every coordinate moved by `sign` times its
// size, in signs that repeat with period 3 and 7, so that no simple mode is
// left out.
std::vector<double> perturbed(std::vector<double> x, const std::vector<double>& e, double sign) {
  for (std::size_t at = 0; at < x.size(); ++at)
    x[at] += sign * ((at % 3 == 0) != (at % 7 == 0) ? -1.0 : 1.0) * e[at];
  return x;
}

// The least-squares slope of y against its index over [from, y.size()).
double log_slope(const std::vector<double>& y, std::size_t from) {
  const double n = static_cast<double>(y.size() - from);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = from; i < y.size(); ++i) {
    const double x = static_cast<double>(i);
    sx += x, sy += y[i], sxx += x * x, sxy += x * y[i];
  }
  const double d = n * sxx - sx * sx;
  return d > 0 ? (n * sxy - sx * sy) / d : 0.0;
}

// rho and its rate from ln(norm) per step (the slope over the second half),
// and the late growth: the largest value over the last quarter over the
// largest over the second (a sum of modes that do not grow has a falling
// envelope, which its beats reach within a quarter).
void fit_growth(const std::vector<double>& log_norm, double window, MatrixFreeRho& r) {
  if (log_norm.size() < 2) return;
  const double per_step = log_slope(log_norm, log_norm.size() / 2);
  r.rho = std::exp(per_step);
  r.rate_per_s = per_step / window;
  const std::size_t q = log_norm.size() / 4;
  if (q == 0) return;
  const auto largest = [&log_norm, q](std::size_t from) {
    return *std::max_element(log_norm.begin() + static_cast<std::ptrdiff_t>(from),
                             log_norm.begin() + static_cast<std::ptrdiff_t>(from + q));
  };
  r.late_growth = std::exp(largest(log_norm.size() - q) - largest(q));
}

}  // namespace

MatrixFreeSettings matrix_free_settings(bool implicit) {
  MatrixFreeSettings f;
  f.implicit = implicit;
  if (f.implicit) {
    f.size = kMatrixFreeImplicitPerturbation;
    f.growth = kMatrixFreeImplicitGrowth;
  }
  return f;
}

MatrixFreeRho measure_matrix_free(const CouplingPasses& c, const MatrixFreeSettings& f, double H,
                                  double window) {
  const std::vector<double> e = perturbation_sizes(c, H, f.size);
  // The unmoved pass drifts from rest by round-off, at the coupling's own
  // rate: it ends where that drift reaches 1e-3 of the static magnitudes
  // (before a node gives up on a diverging step), and the measure with it.
  std::vector<std::vector<double>> unmoved;
  c.pass(perturbed(c.rest, e, 0.0), [&](const std::vector<double>& y) {
    double drift = 0;
    for (std::size_t i = 0; i < y.size(); ++i)
      drift = std::max(drift, std::abs(y[i] - c.rest[i]) * f.size / e[i]);
    if (!(drift < kMatrixFreeDrift)) return false;
    unmoved.push_back(y);
    return true;
  });
  const double first = std::sqrt(static_cast<double>(e.size()));
  std::vector<double> log_norm;
  MatrixFreeRho r;
  long j = 0;  // the steps of the moved pass so far
  c.pass(perturbed(c.rest, e, 1.0), [&](const std::vector<double>& y) {
    const auto at = static_cast<std::size_t>(j);
    if (at >= unmoved.size()) return false;
    double sum = 0;
    for (std::size_t i = 0; i < y.size(); ++i) sum += std::pow((y[i] - unmoved[at][i]) / e[i], 2);
    const double norm = std::sqrt(sum);
    if (!std::isfinite(norm)) return false;
    log_norm.push_back(std::log(std::max(norm, 1e-300)));
    r.steps = j + 1;
    r.growth = norm / first;
    if (j == 0) r.carried = r.growth;
    ++j;
    return r.growth < f.growth;
  });
  fit_growth(log_norm, window, r);
  return r;
}

long matrix_free_steps(double t_end, double H, long ratio) {
  return std::min(kMatrixFreeMaxSteps,
                  kMatrixFreeRunLengths * std::lround(t_end / H / static_cast<double>(ratio)));
}

void add_matrix_free_note(RunRecord& run, const std::string& note) {
  run.spectral_note += (run.spectral_note.empty() ? "" : "; ") + note;
}

void judge_matrix_free(RunRecord& run, const MatrixFreeRho& m, const MatrixFreeSettings& f,
                       double t_end) {
  if (f.implicit && !(m.carried >= kMatrixFreeCarried)) {
    std::ostringstream s;
    s << "not measured: the perturbation of the coupling data fell to " << m.carried
      << " of itself in the first step, which takes them in one pass, so it did not reach "
         "the participants' inner states";
    add_matrix_free_note(run, s.str());
    return;
  }
  run.matrix_free_rho = m.rho;
  run.matrix_free_rate = m.rate_per_s;
  run.matrix_free_steps = m.steps;
  const bool grew = m.growth >= f.growth || m.late_growth >= kMatrixFreeLateGrowth;
  if (grew && m.rate_per_s >= unstable_rate(t_end)) {
    run.stability = "unstable";
    run.stability_basis = "matrix-free";
    run.spectral_radius = m.rho;
    run.spectral_rate = m.rate_per_s;
  }
}

}  // namespace railcosim::verdict
