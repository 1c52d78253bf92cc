// A bound on the time one piece of work may take on this thread (a node's
// macro step), and a way to ask it to stop early (the node was told to shut
// down). The integrator looks at both as it goes and gives up with
// StepFailure; code that sets neither is never interrupted.
#pragma once

#include <atomic>
#include <chrono>
#include <string>

namespace railcosim {

struct WorkBudget {
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  std::chrono::milliseconds limit{0};         // for the message
  const std::atomic<bool>* cancel = nullptr;  // set: stop as soon as possible
};

// The budget of the work running on this thread.
WorkBudget& current_work_budget();

// Sets the budget of this thread for its lifetime.
class ScopedWorkBudget {
 public:
  ScopedWorkBudget(std::chrono::milliseconds limit, const std::atomic<bool>* cancel);
  ~ScopedWorkBudget();
  ScopedWorkBudget(const ScopedWorkBudget&) = delete;
  ScopedWorkBudget& operator=(const ScopedWorkBudget&) = delete;

 private:
  WorkBudget saved_;
};

// Why the work must stop ("" while it may go on).
std::string work_budget_exceeded();

}  // namespace railcosim
