// `master run`'s options of what is judged after the run (run::JudgeOptions).
#include <CLI/CLI.hpp>

#include "cli/cli_run.hpp"

namespace railcosim::cli {

// What is judged after the run, and within what budget (run::JudgeOptions).
void add_judge_options(CLI::App* run, RunArgs& a) {
  run->add_option("--judge", a.judge,
                  "What is judged after the run: full (stability and the errors against the "
                  "reference), stability (no reference is made), none")
      ->check(CLI::IsMember({"full", "stability", "none"}))
      ->capture_default_str();
  run->add_option("--judge-budget", a.judge_budget,
                  "Where the stability map is measured by Arnoldi's method (a model of more than "
                  "4000 coordinates), its products may take this many times the run's macro "
                  "steps (at least 200 products); past it the stability is \"not judged\" with "
                  "the reason. A smaller model's map is taken whole. 0: no bound")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
}

}  // namespace railcosim::cli
