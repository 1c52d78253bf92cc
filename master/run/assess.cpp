#include "run/assess.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "connection.hpp"
#include "log.hpp"
#include "run/matrix_free.hpp"
#include "run/spectral.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/judge_options.hpp"

namespace railcosim::run {

// Run in process only: its fields are changed behind its text, which the
// master would refuse to send to a node (check_scene_text).
Scene parked_scene(const Scene& scene, double macro_step) {
  Scene s = scene;
  s.speed = 0;
  const long wanted =
      std::max(verdict::kProbeMinSteps, std::lround(std::ceil(verdict::kProbeTime / macro_step)));
  const long most = std::max(1L, std::lround(scene.end_time / macro_step));
  s.end_time = static_cast<double>(std::min(wanted, most)) * macro_step;
  return s;
}

verdict::Stability probe_stability(const Scene& scene, const CaseSpec& spec,
                                   const RunOptions& options) {
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
  return verdict::probe_growth(r, options.macro_step,
                               options.coupling.method == engine::CouplingMethod::kImplicit,
                               options.coupling.convergence);
}

namespace {

// The map's verdict, or the probe's where the map's steps cannot be
// iterated to convergence (implicit coupling); "not judged" with the
// reason where the measure does not converge within its budget. The run's
// stop flag (and the signal that interrupts a wait) is asked before every
// product of the map.
void judge_growth(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                  const RunOptions& options) {
  const std::atomic<int>* stop = options.stop;
  verdict::MapSettings settings;
  settings.budget = verdict::judge_budget(run.macro_steps, options.judge, [stop] {
    return (stop && stop->load() != 0) || interrupt_signal() != 0;
  });
  verdict::MapSpectrum m;
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
  const bool implicit = options.coupling.method == engine::CouplingMethod::kImplicit;
  if (!verdict::judge_by_map(run, m, scene.end_time, implicit)) return;
  verdict::judge_by_probe(run, probe_stability(scene, spec, options));
  // Implicit coupling has no map here: its rho through the participants.
  judge_growth_matrix_free(run, scene, spec, options, remote::kInprocTransport, {});
}

}  // namespace

void assess_growth(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                   const RunOptions& options, bool probe) {
  // A node the user started may run a model of its own behind the scene's
  // name: the map and the probe, built from the scene, would judge the
  // built-in model instead.
  if (!probe) {
    verdict::judge_without_model(run, options.macro_step);
    return;
  }
  if (run.status == "failed") return;
  judge_growth(run, scene, spec, options);
  verdict::judge_defect(run, options.macro_step);
}

void assess(RunRecord& run, const RunRecord& reference, const Scene& scene, const CaseSpec& spec,
            const RunOptions& options, bool probe) {
  assess_growth(run, scene, spec, options, probe);
  verdict::judge(run, reference, scene);
}

}  // namespace railcosim::run
