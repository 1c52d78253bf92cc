// The stepping loop of a co-simulation run, and how a run ends before its
// last macro step: interrupted, diverged (a displacement over the scene's
// bound, a value not finite, or an integrator that gave up while the
// reported values show growth), failed (an integrator that gave up while
// they show none: a participant's word alone) or not converged (the
// implicit iterations' budget spent).
#pragma once

#include <functional>
#include <vector>

#include "engine/step_executor.hpp"
#include "run/run_record.hpp"
#include "run/runner.hpp"

namespace railcosim::run {

// Throws std::runtime_error when the run's stop flag is set (a signal).
void check_stop(const RunOptions& o, long n);

// Macro steps 0 .. N - 1 of `steps`, each handed to `record_row`, until the
// end or a run-ending event (recorded in r's status and message); `last`:
// the participants' results at the start (initialize). Returns the macro
// steps done.
long step_through(RunRecord& r, engine::MacroSteps& steps, const Scene& scene, const RunOptions& o,
                  long N, double bound,
                  const std::function<void(long, const std::vector<StepResult>&)>& record_row,
                  std::vector<StepResult> last);

}  // namespace railcosim::run
