#include "work_budget.hpp"

#include <utility>

namespace railcosim {

WorkBudget& current_work_budget() {
  thread_local WorkBudget budget;
  return budget;
}

ScopedWorkBudget::ScopedWorkBudget(std::chrono::milliseconds limit, const std::atomic<bool>* cancel)
    : saved_(current_work_budget()) {
  WorkBudget& b = current_work_budget();
  if (limit.count() > 0) b.deadline = std::chrono::steady_clock::now() + limit;
  b.limit = limit;
  b.cancel = cancel;
}

ScopedWorkBudget::~ScopedWorkBudget() {
  current_work_budget() = saved_;
}

std::string work_budget_exceeded() {
  const WorkBudget& b = current_work_budget();
  if (b.cancel && b.cancel->load()) return "the node is shutting down";
  if (std::chrono::steady_clock::now() > b.deadline) {
    std::string s = "the macro step took longer than this node's limit of ";
    s += std::to_string(b.limit.count());
    s += " ms of work (--max-step-seconds)";
    return s;
  }
  return "";
}

void work_progress(std::uint64_t micro_steps) {
  WorkBudget& b = current_work_budget();
  b.done += micro_steps;
  if (!b.on_progress) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - b.last_progress < b.progress_every) return;
  b.last_progress = now;
  b.on_progress(b.done);
}

ScopedWorkProgress::ScopedWorkProgress(std::function<void(std::uint64_t)> on_progress,
                                       std::chrono::milliseconds every)
    : saved_(std::move(current_work_budget().on_progress)),
      saved_done_(current_work_budget().done) {
  WorkBudget& b = current_work_budget();
  b.on_progress = std::move(on_progress);
  b.progress_every = every;
  b.last_progress = std::chrono::steady_clock::now();  // the first after one interval
  b.done = 0;
}

ScopedWorkProgress::~ScopedWorkProgress() {
  WorkBudget& b = current_work_budget();
  b.on_progress = std::move(saved_);
  b.done = saved_done_;
}

}  // namespace railcosim
