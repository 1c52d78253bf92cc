#include "run/matrix_free.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <memory>
#include <sstream>

#include "engine/coupled_statics.hpp"
#include "engine/window_schedule.hpp"
#include "newmark.hpp"
#include "run/parked.hpp"
#include "scene_text.hpp"
#include "verdict/stability.hpp"

namespace railcosim::run {
namespace {

using FreeMemory = engine::CoupledSteps::Memory;

// Every output the master holds (each participant's at t_n), in one fixed
// order, with its kind: 0 displacement, 1 velocity, 2 force.
template <class M, class F>
void each_output(M& memory, F&& f) {
  for (auto& cd : memory.out)
    for (auto& d : cd) {
      for (auto& x : d.displacement) f(x, 0);
      for (auto& x : d.velocity) f(x, 1);
      for (auto& x : d.force) f(x, 2);
    }
}

std::vector<double> outputs_of(FreeMemory m) {
  std::vector<double> v;
  each_output(m, [&v](double x, int) { v.push_back(x); });
  return v;
}

// The perturbation of each output: `size` times the largest displacement
// (force) at rest; a velocity as a displacement over H.
std::vector<double> perturbation_sizes(FreeMemory m, double H, double size) {
  double u = 0, f = 0;
  each_output(m, [&](double x, int kind) {
    if (kind == 0) u = std::max(u, std::abs(x));
    if (kind == 2) f = std::max(f, std::abs(x));
  });
  const double du = size * (u > 0 ? u : 1e-3);
  const double df = size * (f > 0 ? f : 1e5);
  std::vector<double> e;
  each_output(m, [&](double, int kind) { e.push_back(kind == 0 ? du : kind == 1 ? du / H : df); });
  return e;
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

}  // namespace

namespace {

// How the measure takes a coupling: an implicit one converged tightly, with
// a larger perturbation (its iterates stand kMatrixFreeConvergence apart)
// that may grow less before it leaves the linear range.
struct FreeSettings {
  RunOptions options;
  double size = kMatrixFreePerturbation;
  double growth = kMatrixFreeGrowth;
  bool implicit = false;
};

FreeSettings free_settings(const RunOptions& run) {
  FreeSettings f;
  f.options = run;
  f.implicit = run.coupling.method == engine::CouplingMethod::kImplicit;
  if (f.implicit) {
    f.options.coupling.convergence = kMatrixFreeConvergence;
    f.options.coupling.max_iterations = kMatrixFreeMaxIterations;
    f.size = kMatrixFreeImplicitPerturbation;
    f.growth = kMatrixFreeImplicitGrowth;
  }
  return f;
}

// The memory at rest with every output moved by `sign` times its size, in
// signs that repeat with period 3 and 7, so that no simple mode is left out.
FreeMemory perturbed(FreeMemory m, const std::vector<double>& e, double sign) {
  std::size_t at = 0;
  each_output(m, [&](double& x, int) {
    x += sign * ((at % 3 == 0) != (at % 7 == 0) ? -1.0 : 1.0) * e[at];
    ++at;
  });
  return m;
}

// Adds to the record's note on rho (the map's, where it could not be built).
void add_matrix_free_note(RunRecord& run, const std::string& note) {
  run.spectral_note += (run.spectral_note.empty() ? "" : "; ") + note;
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

MatrixFreeRho matrix_free_rho(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                              const std::string& transport, const remote::TransportSetup& setup,
                              long max_steps) {
  const double H = options.macro_step;
  const FreeSettings f = free_settings(options);
  // A step of the map: the macro step, or a multirate plan's slow window.
  const double window = H * static_cast<double>(rate_plan(scene, spec, options).ratio);
  const Scene parked = with_keys(
      scene, {{"vehicle.speed_kmh", 0.0},
              {"simulation.macro_step", H},
              {"simulation.end_time",
               static_cast<double>(ParkedParticipants::kStart + max_steps + 1) * window}});
  const remote::SceneTransport t =
      remote::make_transport(remote::parse_transport(transport, "transport"), parked, setup);
  auto c = std::make_unique<ParkedParticipants>(parked, spec, f.options, t.factory);
  const std::vector<double> e = perturbation_sizes(c->rest, H, f.size);
  bool fresh = true;  // c has not stepped since its save
  // One pass from the saved state at rest, every output moved by `sign`
  // times its size; `step` is called with the outputs after each macro step
  // and returns whether to go on.
  auto pass = [&](double sign, const std::function<bool(long, const std::vector<double>&)>& step) {
    // An implicit step saves its participants at every step, and a soil may
    // keep only its latest states: an implicit pass starts from a parked
    // co-simulation of its own (the same static state, the same two steps).
    if (f.implicit && !fresh) {
      c.reset();  // its sessions end before the nodes serve the next ones
      c = std::make_unique<ParkedParticipants>(parked, spec, f.options, t.factory);
    }
    fresh = false;
    const FreeMemory start = perturbed(c->rest, e, sign);
    for (std::size_t p = 0; p < c->ps.size(); ++p) c->ps[p]->restore(c->saved[p]);
    c->schedule->set_memory(start);
    // An implicit pass's first step takes one pass from the moved memory:
    // a converged step would iterate the move away before it reached the
    // participants' inner states, where the implicit map's state lives.
    if (f.implicit) c->schedule->single_pass_next();
    for (long j = 0; j < max_steps; ++j) {
      try {
        c->schedule->advance_map(ParkedParticipants::kStart + j);
      } catch (const StepFailure&) {
        return;  // the perturbation ran away: the steps before it measure the growth
      }
      if (!step(j, outputs_of(c->schedule->memory()))) return;
    }
  };
  // The unmoved pass drifts from rest by round-off, at the coupling's own
  // rate: it ends where that drift reaches 1e-3 of the static magnitudes
  // (before a node gives up on a diverging step), and the measure with it.
  const std::vector<double> rest = outputs_of(c->rest);
  std::vector<std::vector<double>> unmoved;
  pass(0.0, [&](long, const std::vector<double>& y) {
    double drift = 0;
    for (std::size_t i = 0; i < y.size(); ++i)
      drift = std::max(drift, std::abs(y[i] - rest[i]) * f.size / e[i]);
    if (!(drift < kMatrixFreeDrift)) return false;
    unmoved.push_back(y);
    return true;
  });
  const double first = std::sqrt(static_cast<double>(e.size()));
  std::vector<double> log_norm;
  MatrixFreeRho r;
  pass(1.0, [&](long j, const std::vector<double>& y) {
    if (static_cast<std::size_t>(j) >= unmoved.size()) return false;
    double sum = 0;
    for (std::size_t i = 0; i < y.size(); ++i) sum += std::pow((y[i] - unmoved[j][i]) / e[i], 2);
    const double norm = std::sqrt(sum);
    if (!std::isfinite(norm)) return false;
    log_norm.push_back(std::log(std::max(norm, 1e-300)));
    r.steps = j + 1;
    r.growth = norm / first;
    if (j == 0) r.carried = r.growth;
    return r.growth < f.growth;
  });
  fit_growth(log_norm, window, r);
  return r;
}

void judge_growth_matrix_free(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                              const RunOptions& options, const std::string& transport,
                              const remote::TransportSetup& setup) {
  if (run.status != "ok") return;
  const FreeSettings f = free_settings(options);
  const long steps =
      std::min(kMatrixFreeMaxSteps,
               kMatrixFreeRunLengths *
                   std::lround(scene.end_time / options.macro_step /
                               static_cast<double>(rate_plan(scene, spec, options).ratio)));
  MatrixFreeRho m;
  try {
    m = matrix_free_rho(scene, spec, options, transport, setup, steps);
  } catch (const std::exception& e) {
    add_matrix_free_note(run, std::string("the matrix-free measure failed: ") + e.what());
    return;
  }
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
  if (grew && m.rate_per_s >= verdict::unstable_rate(scene.end_time)) {
    run.stability = "unstable";
    run.stability_basis = "matrix-free";
    run.spectral_radius = m.rho;
    run.spectral_rate = m.rate_per_s;
  }
}

}  // namespace railcosim::run
