#include "work_budget.hpp"

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

}  // namespace railcosim
