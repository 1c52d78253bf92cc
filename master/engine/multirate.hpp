// The executor of a multirate step plan (rate_plan.hpp): the outer level
// (the fast group and the slow participants at the slow window M H) run by
// a StepExecutor, the fast group's fine windows by its own (fast_group.hpp).
// It hands the run's loop the results of every fine window H, as a
// single-rate run's: the fast participants' own; a slow participant's at
// the end of its window, and in between the straight line from its last
// result to that one (its values are only known at its window's ends).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/fast_group.hpp"

namespace railcosim::engine {

class MultirateExecutor final : public CoupledSteps {
 public:
  // `participants`: every participant of the case, in load order;
  // `static_inputs`: their inputs in the coupled static state. Throws
  // std::invalid_argument for options that do not exist.
  MultirateExecutor(RatePlan rates, std::vector<Participant*> participants,
                    const std::vector<CouplingData>& static_inputs, Scheme scheme,
                    CouplingOptions coupling, std::vector<std::string> roles, double fine_step);

  // Every participant's results at t = 0 (in load order).
  std::vector<StepResult> initialize(const std::vector<CouplingData>& inputs) override;
  // Fine window n's results; the slow window holding it is stepped at its
  // first fine window. Windows must come in order.
  std::vector<StepResult> advance(long n) override;

  const RatePlan& rates() const { return rates_; }
  // The outer level's plan and its iterations (implicit coupling).
  const StepPlan& plan() const { return outer_->plan(); }
  const ConvergenceLog& log() const override { return outer_->log(); }
  // Both levels' memories: the outer level's participants, then the inner
  // level's (their outputs, and their past points side by side).
  Memory memory() const override;
  void set_memory(Memory m) override;
  long map_windows() const override { return rates_.ratio; }
  // The outer level's next step (the slow window's) takes its first pass.
  void single_pass_next() override { outer_->single_pass_next(); }
  // The inner level's iterations (of every pass, re-runs included).
  const ConvergenceLog& inner_log() const { return group_->inner().log(); }

 private:
  RatePlan rates_;
  std::vector<Participant*> ps_;
  std::unique_ptr<FastGroup> group_;
  std::unique_ptr<StepExecutor> outer_;
  std::vector<StepResult> slow_last_;  // per participant (slow ones): at the window's start
  std::vector<std::vector<StepResult>> window_;  // per fine window of the current slow window
  long window_at_ = -1;                          // its index
};

// THE coupling of a case on the master: the schedule of its scheme at one
// rate, or the multirate executor when `rates` has two. `static_inputs`:
// the participants' inputs in the coupled static state.
std::unique_ptr<CoupledSteps> make_coupled_steps(
    const RatePlan& rates, Scheme scheme, Feedthrough feedthrough, const CouplingOptions& coupling,
    std::vector<Participant*> participants, Routing routing, std::vector<std::string> roles,
    double macro_step, const std::vector<CouplingData>& static_inputs);

}  // namespace railcosim::engine
