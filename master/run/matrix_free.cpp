#include "run/matrix_free.hpp"

#include <exception>
#include <functional>
#include <memory>

#include "engine/coupled_statics.hpp"
#include "engine/window_schedule.hpp"
#include "newmark.hpp"
#include "run/parked.hpp"
#include "scene_text.hpp"

namespace railcosim::run {
namespace {

using FreeMemory = engine::CoupledSteps::Memory;
using Kind = verdict::CouplingPasses::Kind;

// Every output the master holds (each participant's at t_n), in one fixed
// order, with its kind.
template <class M, class F>
void each_output(M& memory, F&& f) {
  for (auto& cd : memory.out)
    for (auto& d : cd) {
      for (auto& x : d.displacement) f(x, Kind::kDisplacement);
      for (auto& x : d.velocity) f(x, Kind::kVelocity);
      for (auto& x : d.force) f(x, Kind::kForce);
    }
}

std::vector<double> outputs_of(FreeMemory m) {
  std::vector<double> v;
  each_output(m, [&v](double x, Kind) { v.push_back(x); });
  return v;
}

// The memory at rest with its outputs replaced by `values` (of the layout
// of outputs_of).
FreeMemory with_outputs(FreeMemory m, const std::vector<double>& values) {
  std::size_t at = 0;
  each_output(m, [&](double& x, Kind) { x = values[at++]; });
  return m;
}

// The options the measure steps with: an implicit coupling converged to
// kMatrixFreeConvergence, in at most kMatrixFreeMaxIterations a step.
RunOptions free_options(RunOptions o) {
  if (o.coupling.method == engine::CouplingMethod::kImplicit) {
    o.coupling.convergence = verdict::kMatrixFreeConvergence;
    o.coupling.max_iterations = verdict::kMatrixFreeMaxIterations;
  }
  return o;
}

}  // namespace

verdict::MatrixFreeRho matrix_free_rho(const Scene& scene, const CaseSpec& spec,
                                       const RunOptions& options, const std::string& transport,
                                       const remote::TransportSetup& setup, long max_steps) {
  const double H = options.macro_step;
  const RunOptions o = free_options(options);
  const verdict::MatrixFreeSettings f =
      verdict::matrix_free_settings(options.coupling.method == engine::CouplingMethod::kImplicit);
  // A step of the map: the macro step, or a multirate plan's slow window.
  const double window = H * static_cast<double>(rate_plan(scene, spec, options).ratio);
  const Scene parked = with_keys(
      scene, {{"vehicle.speed_kmh", 0.0},
              {"simulation.macro_step", H},
              {"simulation.end_time",
               static_cast<double>(ParkedParticipants::kStart + max_steps + 1) * window}});
  const remote::SceneTransport t =
      remote::make_transport(remote::parse_transport(transport, "transport"), parked, setup);
  auto c = std::make_unique<ParkedParticipants>(parked, spec, o, t.factory);
  verdict::CouplingPasses passes;
  passes.rest = outputs_of(c->rest);
  each_output(c->rest, [&passes](double, Kind kind) { passes.kinds.push_back(kind); });
  bool fresh = true;  // c has not stepped since its save
  passes.pass = [&](const std::vector<double>& values,
                    const std::function<bool(const std::vector<double>&)>& after_step) {
    // An implicit step saves its participants at every step, and a soil may
    // keep only its latest states: an implicit pass starts from a parked
    // co-simulation of its own (the same static state, the same two steps).
    if (f.implicit && !fresh) {
      c.reset();  // its sessions end before the nodes serve the next ones
      c = std::make_unique<ParkedParticipants>(parked, spec, o, t.factory);
    }
    fresh = false;
    const FreeMemory start = with_outputs(c->rest, values);
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
      if (!after_step(outputs_of(c->schedule->memory()))) return;
    }
  };
  return verdict::measure_matrix_free(passes, f, H, window);
}

void judge_growth_matrix_free(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                              const RunOptions& options, const std::string& transport,
                              const remote::TransportSetup& setup) {
  if (run.status != "ok") return;
  const verdict::MatrixFreeSettings f =
      verdict::matrix_free_settings(options.coupling.method == engine::CouplingMethod::kImplicit);
  const long steps = verdict::matrix_free_steps(scene.end_time, options.macro_step,
                                                rate_plan(scene, spec, options).ratio);
  verdict::MatrixFreeRho m;
  try {
    m = matrix_free_rho(scene, spec, options, transport, setup, steps);
  } catch (const std::exception& e) {
    verdict::add_matrix_free_note(run, std::string("the matrix-free measure failed: ") + e.what());
    return;
  }
  verdict::judge_matrix_free(run, m, f, scene.end_time);
}

}  // namespace railcosim::run
