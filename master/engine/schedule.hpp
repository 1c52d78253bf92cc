// Co-simulation schedules: the order in which the participants exchange
// values and step over one macro step [nH, (n+1)H]. The order itself is the
// step plan's (step_plan.hpp: plan_steps()); every schedule is the one
// executor of that plan (step_executor.hpp), named here by its scheme. The
// master's loop knows none of them, and none knows how many participants
// there are or what they hold.
#pragma once

#include <memory>
#include <vector>

#include "cosim_case.hpp"
#include "engine/step_executor.hpp"
#include "engine/step_plan.hpp"
#include "model.hpp"
#include "participant.hpp"

namespace railcosim::engine {

// A schedule: the executor of a step plan.
using Schedule = StepExecutor;

// Parallel: every participant takes its inputs from the others' outputs at
// t_n and they step at the same time (every step is started before any is
// awaited). Lagged: a force output is the one computed at the end of the
// sender's last step. Resolved: the senders of forces first receive their
// fresh displacements, then their forces are read, so the receivers get
// F(state at t_n, inputs at t_n).
class JacobiSchedule final : public Schedule {
 public:
  JacobiSchedule(std::vector<Participant*> participants, Routing routing, Feedthrough feedthrough)
      : Schedule(std::move(participants), std::move(routing),
                 PlanOptions{Scheme::kJacobi, feedthrough, false}) {}
};

// Sequential, in load order: each participant steps with the freshest
// outputs of those before it (at t_n + H) and of those after it (at t_n).
class GaussSeidelSchedule final : public Schedule {
 public:
  GaussSeidelSchedule(std::vector<Participant*> participants, Routing routing)
      : Schedule(std::move(participants), std::move(routing),
                 PlanOptions{Scheme::kGaussSeidel, Feedthrough::kLagged, false}) {}
};

// Throws std::invalid_argument for a combination that does not exist
// (resolved feedthrough under Gauss–Seidel).
std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        std::vector<Participant*> participants, Routing routing);

}  // namespace railcosim::engine
