// What a run's verdict measures after the run (--judge) and within what
// budget (--judge-budget).
#pragma once

#include <functional>
#include <string>

#include "verdict/spectrum.hpp"

namespace railcosim::verdict {

enum class JudgeMode {
  kFull,       // stability and the errors against the reference
  kStability,  // stability only: no reference is made, the errors are not judged
  kNone,       // nothing: the run is "not judged"
};
std::string to_string(JudgeMode m);
// Throws std::invalid_argument naming `what` and the valid values.
JudgeMode parse_judge_mode(const std::string& s, const std::string& what);

struct JudgeOptions {
  JudgeMode mode = JudgeMode::kFull;
  // Where the map is measured by Arnoldi's method (more coordinates than
  // map_measure.hpp's kDenseMapLimit): its products may take this many times
  // the run's own macro steps in parked macro steps (two a product), and at
  // least kJudgeMinProducts products; past it the run's stability is "not
  // judged" with the reason. 0: no bound. A smaller map is taken whole.
  double budget = 1.0;
};
inline constexpr long kJudgeMinProducts = 200;

// The measure's budget for a run of `macro_steps` steps: Arnoldi's products
// (each two parked macro steps) at most options.budget times half the run's
// macro steps, and at least kJudgeMinProducts; a count, not a time, so that
// the verdict does not depend on the machine's load. `stop` is asked before
// every product.
Budget judge_budget(long macro_steps, const JudgeOptions& options, std::function<bool()> stop);

}  // namespace railcosim::verdict
