// `master run` arguments as the command line parses them, for the tests of
// the run's options (scene defaults, cut windows).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "cli/cli_run.hpp"
#include "test_support.hpp"

namespace railcosim::test {

// `master run --scene scenes/paper.toml --case wr-xx-gauss-seidel FLAGS`.
struct ParsedRun {
  CLI::App app;
  cli::RunArgs args;
  explicit ParsedRun(const std::string& flags) {
    cli::add_run_command(app, args);
    app.parse(
        "run --scene " + source_path("scenes/paper.toml") + " --case wr-xx-gauss-seidel " + flags,
        false);
  }
};

}  // namespace railcosim::test
