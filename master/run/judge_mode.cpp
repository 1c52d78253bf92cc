// The names of what a run's verdict measures (runner.hpp: JudgeMode), as
// users spell them on the command line and in a study's plan.
#include <stdexcept>
#include <string>

#include "run/runner.hpp"

namespace railcosim::run {

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

}  // namespace railcosim::run
