#include "run/spectral.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "engine/coupled_statics.hpp"
#include "engine/window_schedule.hpp"
#include "run/assess.hpp"
#include "run/parked.hpp"
#include "subsystem.hpp"
#include "subsystem_motion.hpp"
#include "verdict/map_measure.hpp"

namespace railcosim::run {
namespace {

using verdict::kMapConvergence;
using verdict::kMapMaxIterations;
using verdict::kMapPerturbation;

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

// The map as a linear operator in coordinates scaled by their
// perturbations: A v is the central difference of two macro steps from the
// state at rest moved by +-c e.v, over 2c e (c = 1 / max|v|, so that no
// coordinate moves by more than its perturbation: the Hertz contact's
// linear range). For a unit vector this is the dense map's column.
verdict::LinearOperator map_operator(ParkedCoupling& c, double H) {
  auto x0 = std::make_shared<const std::vector<double>>(c.rest());
  auto e = std::make_shared<const std::vector<double>>(perturbations(*x0, c.kinds(), H));
  verdict::LinearOperator a;
  a.dimension = static_cast<long>(x0->size());
  a.apply = [&c, x0, e](const double* v, double* y) {
    const std::size_t N = x0->size();
    double largest = 0;
    for (std::size_t i = 0; i < N; ++i) largest = std::max(largest, std::abs(v[i]));
    if (!(largest > 0)) {
      std::fill(y, y + N, 0.0);
      return;
    }
    const double scale = 1 / largest;
    std::vector<double> x = *x0;
    for (std::size_t i = 0; i < N; ++i) x[i] = (*x0)[i] + scale * (*e)[i] * v[i];
    const std::vector<double> up = c.step(x);
    for (std::size_t i = 0; i < N; ++i) x[i] = (*x0)[i] - scale * (*e)[i] * v[i];
    const std::vector<double> down = c.step(x);
    for (std::size_t i = 0; i < N; ++i) y[i] = (up[i] - down[i]) / (2 * scale * (*e)[i]);
  };
  return a;
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

// The scene parked for the map: its step the map's (a multirate plan's slow
// window), its micro steps those the step at rest takes, fixed.
Scene parked_for_map(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                     const RunOptions& o) {
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
  return parked;
}

}  // namespace

Eigen::MatrixXd macro_step_matrix(const Scene& scene, const CaseSpec& spec,
                                  const RunOptions& options) {
  const RunOptions o = map_options(options);
  const Scene parked = parked_for_map(scene, spec, options, o);
  ParkedCoupling c(parked, spec, o);
  return verdict::dense_matrix(map_operator(c, options.macro_step));
}

verdict::MapSpectrum macro_step_spectrum(const Scene& scene, const CaseSpec& spec,
                                         const RunOptions& options,
                                         const verdict::MapSettings& settings) {
  const RunOptions o = map_options(options);
  const auto t0 = std::chrono::steady_clock::now();
  const double window =
      options.macro_step * static_cast<double>(rate_plan(scene, spec, options).ratio);
  const Scene parked = parked_for_map(scene, spec, options, o);
  ParkedCoupling c(parked, spec, o);
  const long states = static_cast<long>(c.state().size());
  const verdict::Spectrum m = verdict::measure_map(map_operator(c, options.macro_step), settings);
  std::string refused;
  if (c.not_converged() > 0) {
    std::ostringstream w;
    w << "the implicit step did not converge to " << kMapConvergence << " within "
      << kMapMaxIterations << " iterations in " << c.not_converged() << " of the map's "
      << 2 * m.products << " steps";
    refused = w.str();
  }
  verdict::MapSpectrum s = verdict::map_spectrum(m, window, refused);
  s.states = states;
  s.micro_steps = c.micro_steps();
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace railcosim::run
