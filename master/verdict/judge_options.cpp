// The names of what a run's verdict measures (judge_options.hpp: JudgeMode),
// as users spell them on the command line and in a study's plan, and the
// measure's budget.
#include "verdict/judge_options.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace railcosim::verdict {

std::string to_string(JudgeMode m) {
  switch (m) {
    case JudgeMode::kFull:
      return "full";
    case JudgeMode::kStability:
      return "stability";
    case JudgeMode::kNone:
      return "none";
  }
  return "full";
}

JudgeMode parse_judge_mode(const std::string& s, const std::string& what) {
  for (JudgeMode m : {JudgeMode::kFull, JudgeMode::kStability, JudgeMode::kNone})
    if (s == to_string(m)) return m;
  throw std::invalid_argument(what + ": '" + s + "' is not one of full, stability, none");
}

Budget judge_budget(long macro_steps, const JudgeOptions& options, std::function<bool()> stop) {
  Budget b;
  if (options.budget > 0)
    b.max_products = std::max(kJudgeMinProducts,
                              std::lround(options.budget * static_cast<double>(macro_steps) / 2));
  b.stop = std::move(stop);
  return b;
}

}  // namespace railcosim::verdict
