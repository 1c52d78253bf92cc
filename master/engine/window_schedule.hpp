// The schedule for inputs that change over the macro step (interpolated or
// extrapolated) and for implicit coupling, where each macro step is repeated
// from a checkpoint until the exchanged values converge: the same executor
// of the same step plan as the plain Jacobi and Gauss–Seidel schedules
// (step_executor.hpp), with coupling options.
//
// Implicit coupling solves the window's fixed point x = G(x) over the plan's
// iterated links:
//   Jacobi (parallel-implicit): x holds every exchanged value at t_n + H;
//     each iteration every participant steps with inputs from x.
//   Gauss–Seidel (serial-implicit): x holds the values that flow against the
//     load order (from a later participant to an earlier one); each
//     iteration the participants step in order, each with the fresh outputs
//     of those before it and with x for those after it.
// The accelerator proposes the next x from x and G(x).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/coupling_options.hpp"
#include "engine/schedule.hpp"

namespace railcosim::engine {

class WindowSchedule final : public Schedule {
 public:
  // `roles` name the participants in the convergence log.
  WindowSchedule(std::vector<Participant*> participants, Routing routing,
                 std::vector<std::string> roles, Scheme scheme, const CouplingOptions& options,
                 double macro_step)
      : Schedule(std::move(participants), std::move(routing),
                 PlanOptions{scheme, Feedthrough::kLagged, false}, options, std::move(roles),
                 macro_step) {}
};

// The schedule for a scheme and coupling options: the plain Jacobi or
// Gauss–Seidel schedule for explicit coupling with held inputs, a
// WindowSchedule otherwise. Throws std::invalid_argument for a combination
// that does not exist.
std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        const CouplingOptions& options,
                                        std::vector<Participant*> participants, Routing routing,
                                        std::vector<std::string> roles, double macro_step);

}  // namespace railcosim::engine
