// A bound on the time one piece of work may take on this thread (a node's
// macro step), and a way to ask it to stop early (the node was told to shut
// down). The integrator looks at both as it goes and gives up with
// StepFailure; code that sets neither is never interrupted.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace railcosim {

struct WorkBudget {
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  std::chrono::milliseconds limit{0};         // for the message
  const std::atomic<bool>* cancel = nullptr;  // set: stop as soon as possible
  // Told, at most once every `progress_every`, how many micro steps the work
  // has taken since `on_progress` was set (a node's progress frames).
  std::function<void(std::uint64_t)> on_progress;
  std::chrono::milliseconds progress_every{100};
  std::chrono::steady_clock::time_point last_progress{};
  std::uint64_t done = 0;
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

// The work has taken `micro_steps` more micro steps (0: it is still at it
// without having finished one): tells on_progress when it is due.
void work_progress(std::uint64_t micro_steps);

// Sets on_progress of this thread's budget for its lifetime (counting from 0).
class ScopedWorkProgress {
 public:
  ScopedWorkProgress(std::function<void(std::uint64_t)> on_progress,
                     std::chrono::milliseconds every);
  ~ScopedWorkProgress();
  ScopedWorkProgress(const ScopedWorkProgress&) = delete;
  ScopedWorkProgress& operator=(const ScopedWorkProgress&) = delete;

 private:
  std::function<void(std::uint64_t)> saved_;
  std::uint64_t saved_done_;
};

}  // namespace railcosim
