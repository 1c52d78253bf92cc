// The deadlines of one macro step a node works on (relayed plane and lock
// step): it must show progress within `quiet` (its step report, or a
// progress frame carrying a later micro step than the last one counted, so
// frames that repeat themselves gain nothing), and the whole step must end
// within `budget` (--step-budget, [coupling] step_budget), however much
// progress it shows. A Statics request is watched the same way: its frames
// carry step -1 (before the run), its quiet time is the reply limit and its
// budget the statics budget (RemoteTimeouts::statics_budget()).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>

#include "wire.hpp"

namespace railcosim::remote {

class StepWatch {
 public:
  using Clock = std::chrono::steady_clock;
  // `statics`: the watch of a Statics request (its texts name the static
  // state and how to raise its limits).
  StepWatch(std::chrono::milliseconds quiet, std::chrono::milliseconds budget,
            Clock::time_point start, bool statics = false)
      : quiet_(quiet), budget_(budget), start_(start), last_(start), statics_(statics) {}

  // A progress frame of the step at macro step `step` (of a Statics: -1,
  // whatever `step` says): "" once taken (counted or not), else why it is
  // not one the master can accept.
  std::string take(const wire::Progress& p, long step, Clock::time_point now);
  // How long the next read may wait (at least 1 ms).
  std::chrono::milliseconds left(Clock::time_point now) const;
  // Why the wait ended at `now`: "no reply within ..." for a node that sent
  // no progress frame at all, "no progress for ..." for one whose frames
  // stopped advancing, "step budget of ... exhausted ..." past the budget.
  std::string why(Clock::time_point now) const;
  // Progress frames counted so far.
  long counted() const { return counted_; }
  // The longest wait so far without a counted frame, until `now`.
  Clock::duration longest_quiet(Clock::time_point now) const {
    return std::max(longest_, now - last_);
  }

 private:
  std::chrono::milliseconds quiet_;
  std::chrono::milliseconds budget_;
  Clock::time_point start_;
  Clock::time_point last_;      // the start, or the last progress frame counted
  Clock::duration longest_{0};  // the longest wait between counted frames
  std::uint64_t micro_ = 0;
  long counted_ = 0;
  long stale_ = 0;  // frames since the last counted that did not advance
  bool statics_ = false;
};

// The step of a Statics request's progress frames (the protocol's "before
// the run").
inline constexpr long kStaticsProgressStep = -1;

// "step budget of 120 s exhausted" with the budget in seconds as given.
std::string budget_text(std::chrono::milliseconds budget);
// "budget of 1200 s exhausted (10 times the step budget: ...)", a Statics'.
std::string statics_budget_text(std::chrono::milliseconds budget);

}  // namespace railcosim::remote
