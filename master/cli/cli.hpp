// The master's command line: `master run`, `master study`, `master conform`
// (cli_run, cli_study, conform).
#pragma once

#include <CLI/CLI.hpp>
#include <atomic>

namespace railcosim::cli {

// A number of seconds in [lo, hi] (CLI::Range lets NaN through).
CLI::Validator seconds_in(double lo, double hi);

// Adds --check to a command: read and check everything, do nothing.
void add_check_flag(CLI::App& command, bool& check);

// Adds --verbose to a command: the master's details (the nodes it starts,
// the static state) on stderr too.
void add_verbose_flag(CLI::App& command);

// Set by SIGINT or SIGTERM once master_main has installed its handlers: runs
// stop at the next macro step and leave a summary saying so.
const std::atomic<int>* stop_flag();

// Parses the arguments and runs the command. Returns the process exit status:
// 0 when every requested run finished, 1 when a run failed, 2 for a usage or
// scene error.
int master_main(int argc, char** argv);

}  // namespace railcosim::cli
