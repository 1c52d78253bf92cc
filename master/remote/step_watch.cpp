#include "remote/step_watch.hpp"

#include <algorithm>
#include <sstream>

#include "remote/remote_participant.hpp"

namespace railcosim::remote {

std::string budget_text(std::chrono::milliseconds budget) {
  std::ostringstream s;
  s << "step budget of " << static_cast<double>(budget.count()) / 1000.0
    << " s exhausted (set [coupling] step_budget or --step-budget for longer macro steps)";
  return s.str();
}

std::string statics_budget_text(std::chrono::milliseconds budget) {
  std::ostringstream s;
  s << "budget of " << static_cast<double>(budget.count()) / 1000.0 << " s exhausted ("
    << RemoteTimeouts::kStaticsBudgetSteps
    << " times the step budget: set [coupling] step_budget or --step-budget to raise it)";
  return s.str();
}

std::string StepWatch::take(const wire::Progress& p, long step, Clock::time_point now) {
  if (statics_ && p.step() != kStaticsProgressStep)
    return "a progress frame for macro step " + std::to_string(p.step()) +
           " during the static state (expected step " + std::to_string(kStaticsProgressStep) + ")";
  if (!statics_ && p.step() != step)
    return "a progress frame for macro step " + std::to_string(p.step()) + " during macro step " +
           std::to_string(step);
  if (p.micro_steps() > micro_) {
    micro_ = p.micro_steps();
    longest_ = std::max(longest_, now - last_);
    last_ = now;
    ++counted_;
    stale_ = 0;
  } else {
    ++stale_;
  }
  return "";
}

std::chrono::milliseconds StepWatch::left(Clock::time_point now) const {
  const auto end = std::min(last_ + quiet_, start_ + budget_);
  return std::max(std::chrono::milliseconds(1),
                  std::chrono::ceil<std::chrono::milliseconds>(end - now));
}

std::string StepWatch::why(Clock::time_point now) const {
  std::ostringstream s;
  if (statics_) s << "static state: ";
  // What the frames count: micro steps, or a Statics' own units of work.
  const char* at = statics_ ? "count" : "micro step";
  if (now >= start_ + budget_) {
    s << (statics_ ? statics_budget_text(budget_) : budget_text(budget_)) << "; " << counted_
      << " progress frame(s) counted, the last at " << at << " " << micro_;
    return s.str();
  }
  if (counted_ == 0 && stale_ == 0) {
    s << "no reply within " << quiet_.count() << " ms";
    if (statics_)
      s << " (the reply limit: a participant that works longer sends progress frames while it "
           "works, or set RAILCOSIM_REPLY_SECONDS)";
    return s.str();
  }
  s << "no progress for " << quiet_.count() << " ms (";
  if (counted_ > 0)
    s << "its last progress frame that counted was at " << at << " " << micro_;
  else
    s << "no progress frame advanced past " << at << " 0";
  if (stale_ > 0) s << "; " << stale_ << " progress frame(s) since then did not advance";
  s << ")";
  return s.str();
}

std::chrono::milliseconds RemoteParticipant::step_deadline() const {
  if (slowest_step_.count() == 0) return timeouts_.step_max;
  const auto scaled = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(slowest_step_) * timeouts_.step_factor);
  return std::clamp(scaled, timeouts_.step_min, timeouts_.step_max);
}

StepResult RemoteParticipant::finish_step() {
  StepWatch watch(step_deadline(), timeouts_.step_budget, step_started_);
  const wire::StepReport w =
      await(wire::Envelope::kStepReport, "step", step_deadline(), &watch).step_report();
  StepResult r = from_wire(w);
  check(check_step_report(r, w.step(), w.t(), step_ + 1, shape_));
  keep_samples(w);
  slowest_step_ = std::max(slowest_step_, std::chrono::steady_clock::now() - step_started_);
  return r;
}

}  // namespace railcosim::remote
