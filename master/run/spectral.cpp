#include "run/spectral.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "engine/coupled_statics.hpp"
#include "engine/window_schedule.hpp"
#include "run/parked.hpp"
#include "run/stability.hpp"
#include "subsystem.hpp"
#include "subsystem_motion.hpp"

namespace railcosim::run {
namespace {

using Memory = engine::CoupledSteps::Memory;

// What a coordinate of the coupled state is, for the size of its perturbation.
enum class Kind { kDisplacement, kVelocity, kAcceleration, kForce };

// Every number of the master's memory in one fixed order, with its kind.
template <class M, class F>
void each_value(M& memory, F&& f) {
  auto data = [&](auto& d) {
    for (auto& x : d.displacement) f(x, Kind::kDisplacement);
    for (auto& x : d.velocity) f(x, Kind::kVelocity);
    for (auto& x : d.force) f(x, Kind::kForce);
  };
  for (auto& cd : memory.out)
    for (auto& d : cd) data(d);
  for (auto& point : memory.past)
    for (auto& cd : point)
      for (auto& d : cd) data(d);
}

// The parked co-simulation (parked.hpp) in the master's process, its
// participants the scene's own subsystems, whose state it sets and reads
// coordinate by coordinate.
class ParkedCoupling {
 public:
  static constexpr long kStart = ParkedParticipants::kStart;

  ParkedCoupling(const Scene& parked, const CaseSpec& spec, const RunOptions& o)
      : parked_(parked, spec, o, [this, &parked](const SubsystemConfig& c) {
          auto s = std::make_unique<Subsystem>(parked, c);
          subs_.push_back(s.get());
          return std::unique_ptr<Participant>(std::move(s));
        }) {}

  // The coupled state now: every participant's motion, then the memory.
  std::vector<double> state() const {
    std::vector<double> x;
    for (const auto& s : subs_) {
      const std::vector<double> m = snapshot_motion(s->save());
      x.insert(x.end(), m.begin(), m.end());
    }
    Memory m = parked_.schedule->memory();
    each_value(m, [&](double v, Kind) { x.push_back(v); });
    return x;
  }

  // The kind of each coordinate of state().
  std::vector<Kind> kinds() const {
    std::vector<Kind> k;
    for (const ParticipantState& saved : parked_.saved) {
      const std::size_t n = snapshot_motion(saved).size() / 3;
      for (Kind kind : {Kind::kDisplacement, Kind::kVelocity, Kind::kAcceleration})
        k.insert(k.end(), n, kind);
    }
    Memory m = parked_.rest;
    each_value(m, [&](double, Kind kind) { k.push_back(kind); });
    return k;
  }

  // One macro step from the state x (of the layout of state()).
  std::vector<double> step(const std::vector<double>& x) {
    std::size_t at = 0;
    for (std::size_t p = 0; p < subs_.size(); ++p) {
      ParticipantState moved = parked_.saved[p];
      const std::size_t n = snapshot_motion(moved).size();
      set_snapshot_motion(moved,
                          std::vector<double>(x.begin() + static_cast<std::ptrdiff_t>(at),
                                              x.begin() + static_cast<std::ptrdiff_t>(at + n)));
      subs_[p]->restore(moved);
      at += n;
    }
    Memory m = parked_.rest;
    each_value(m, [&](double& v, Kind) { v = x[at++]; });
    parked_.schedule->set_memory(std::move(m));
    std::vector<long> before;
    for (const auto& s : subs_) before.push_back(s->integrator_state().micro_steps);
    parked_.schedule->advance_map(kStart);
    // Per a participant's own macro step (a multirate map step spans several
    // of the fast participants').
    const long windows = parked_.schedule->map_windows();
    for (std::size_t p = 0; p < subs_.size(); ++p)
      micro_ = std::max(micro_, (subs_[p]->integrator_state().micro_steps - before[p]) *
                                    parked_.rates.window[p] / windows);
    return state();
  }

  // The most micro steps a participant took in one step().
  long micro_steps() const { return micro_; }
  // The implicit steps that hit the iteration limit so far.
  long not_converged() const { return parked_.schedule->log().not_converged; }

  // Back to the saved state of rest.
  std::vector<double> rest() {
    for (std::size_t p = 0; p < subs_.size(); ++p) subs_[p]->restore(parked_.saved[p]);
    parked_.schedule->set_memory(parked_.rest);
    return state();
  }

 private:
  std::vector<Subsystem*> subs_;  // the participants of parked_, as the integrators they are
  ParkedParticipants parked_;
  long micro_ = 0;
};

// The perturbation of each coordinate: kMapPerturbation of the largest
// displacement (of the largest force) at rest; velocities and accelerations
// as a displacement over H and H^2.
std::vector<double> perturbations(const std::vector<double>& x, const std::vector<Kind>& kinds,
                                  double H) {
  double u = 0, f = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (kinds[i] == Kind::kDisplacement) u = std::max(u, std::abs(x[i]));
    if (kinds[i] == Kind::kForce) f = std::max(f, std::abs(x[i]));
  }
  const double du = kMapPerturbation * (u > 0 ? u : 1e-3);
  const double df = kMapPerturbation * (f > 0 ? f : 1e5);
  std::vector<double> e(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    switch (kinds[i]) {
      case Kind::kDisplacement:
        e[i] = du;
        break;
      case Kind::kVelocity:
        e[i] = du / H;
        break;
      case Kind::kAcceleration:
        e[i] = du / (H * H);
        break;
      case Kind::kForce:
        e[i] = df;
        break;
    }
  }
  return e;
}

// The map's matrix in coordinates scaled by their perturbations, the
// columns the step ignores dropped (with their rows).
Eigen::MatrixXd map_matrix(ParkedCoupling& c, double H) {
  const std::vector<double> x0 = c.rest();
  const std::vector<double> e = perturbations(x0, c.kinds(), H);
  const std::size_t N = x0.size();
  Eigen::MatrixXd A(static_cast<Eigen::Index>(N), static_cast<Eigen::Index>(N));
  std::vector<Eigen::Index> kept;
  for (std::size_t j = 0; j < N; ++j) {
    std::vector<double> x = x0;
    x[j] = x0[j] + e[j];
    const std::vector<double> up = c.step(x);
    x[j] = x0[j] - e[j];
    const std::vector<double> down = c.step(x);
    bool any = false;
    for (std::size_t i = 0; i < N; ++i) {
      const double a = (up[i] - down[i]) / (2 * e[i]);
      A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = a;
      any = any || a != 0;
    }
    if (any) kept.push_back(static_cast<Eigen::Index>(j));
  }
  const auto K = static_cast<Eigen::Index>(kept.size());
  Eigen::MatrixXd R(K, K);
  for (Eigen::Index i = 0; i < K; ++i)
    for (Eigen::Index j = 0; j < K; ++j)
      R(i, j) = A(kept[static_cast<std::size_t>(i)], kept[static_cast<std::size_t>(j)]);
  return R;
}

// The options the map steps with: an implicit coupling converged to
// kMapConvergence (its columns then carry that error over the perturbation,
// 1e-6 of the static values), with no budget of iterations.
RunOptions map_options(RunOptions o) {
  if (o.coupling.method == engine::CouplingMethod::kImplicit) {
    o.coupling.convergence = kMapConvergence;
    o.coupling.max_iterations = kMapMaxIterations;
    o.coupling.iteration_budget = 0;
  }
  return o;
}

}  // namespace

MapSpectrum macro_step_spectrum(const Scene& scene, const CaseSpec& spec,
                                const RunOptions& options) {
  MapSpectrum s;
  const RunOptions o = map_options(options);
  const auto t0 = std::chrono::steady_clock::now();
  // A step of the map: the macro step, or a multirate plan's slow window.
  const double window =
      options.macro_step * static_cast<double>(rate_plan(scene, spec, options).ratio);
  Scene parked = parked_scene(scene, window);
  if (parked.micro_steps == 0) {
    // Adaptive micro steps: the map is the step at rest's, with the micro
    // steps it takes there, fixed, so that a perturbation does not change
    // their number (the error control would refine a step for a
    // perturbation of 1e-9 m at a stiff rail node).
    ParkedCoupling at_rest(parked, spec, o);
    at_rest.step(at_rest.rest());
    parked.micro_steps = static_cast<int>(std::max(1L, at_rest.micro_steps()));
  }
  ParkedCoupling c(parked, spec, o);
  s.states = static_cast<long>(c.state().size());
  const Eigen::MatrixXd A = map_matrix(c, options.macro_step);
  s.dimension = static_cast<long>(A.rows());
  s.micro_steps = c.micro_steps();
  if (c.not_converged() > 0) {
    std::ostringstream w;
    w << "the implicit step did not converge to " << kMapConvergence << " within "
      << kMapMaxIterations << " iterations in " << c.not_converged() << " of the map's "
      << 2 * s.states << " steps";
    s.why_not = w.str();
    return s;
  }
  if (A.rows() > 0) {
    const Eigen::EigenSolver<Eigen::MatrixXd> eig(A, false);
    if (eig.info() != Eigen::Success) {
      s.why_not = "the eigenvalue iteration of the map's matrix did not converge";
      return s;
    }
    Eigen::Index at = 0;
    s.rho = eig.eigenvalues().cwiseAbs().maxCoeff(&at);
    s.frequency_hz = std::abs(std::arg(eig.eigenvalues()(at))) / (2 * M_PI * window);
  }
  s.rate_per_s = std::log(std::max(s.rho, 1e-300)) / window;
  s.computed = true;
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace railcosim::run
