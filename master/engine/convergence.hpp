// What an implicit run's iterations did: the residual of every coupled
// quantity per iteration and macro step.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace railcosim::engine {

struct ConvergenceRow {
  long step = 0;                 // macro step n: the window [nH, (n+1)H]
  int iteration = 0;             // 1, 2, ...
  std::vector<double> residual;  // relative residual per quantity (window_schedule.hpp)
};

struct ConvergenceLog {
  std::vector<std::string> quantities;  // e.g. "track_to_vehicle_displacement"
  using Row = ConvergenceRow;
  std::vector<Row> rows;
  std::vector<int> iterations;  // per macro step
  long not_converged = 0;       // macro steps that hit the iteration limit
  long first_not_converged = -1;
  long total = 0;  // iterations over the run so far
};

// Implicit coupling: the run's iterations reached their budget
// (CouplingOptions::iteration_budget) before macro step `step` converged.
class IterationBudgetSpent : public std::runtime_error {
 public:
  IterationBudgetSpent(long budget_, long step_)
      : std::runtime_error("the implicit iterations reached the run's budget of " +
                           std::to_string(budget_) +
                           " (--iteration-budget, [coupling] iteration_budget)"),
        budget(budget_),
        step(step_) {}
  long budget, step;
};

}  // namespace railcosim::engine
