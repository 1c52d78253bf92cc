// `master study`: its options, and a study run, planned or collected.
#pragma once

#include <string>
#include <vector>

#include "remote/transport_names.hpp"

namespace CLI {
class App;
}

namespace railcosim::cli {

struct StudyArgs {
  CLI::App* command = nullptr;
  std::string scene_path;
  std::string out = "results";
  int jobs = 0;
  std::vector<double> macro_steps;
  std::vector<double> tolerances = {1e-5, 1e-6, 1e-7, 1e-8, 1e-9};
  std::string transport = remote::kTcpTransport;
  std::vector<std::string> sweeps;  // KEY=V1,V2,...
  std::string plan;                 // --plan FILE: write the plan only
  std::string collect;              // --collect DIR: read the runs, write the report
  std::string master;               // the program a plan's command lines call
  std::vector<std::string> nodes;   // --node ROLE=HOST:PORT: participants already running
  double budget = 0;
  std::vector<std::string> cases;  // --cases: study only these                // --budget SECONDS:
                                   // runs not started by then are not run
  bool check = false;              // master --check: make the plan, run nothing
};

// Adds `study` to the master's command line, filling `a`.
void add_study_command(CLI::App& app, StudyArgs& a);
// Runs, plans or collects the study; the exit status (0 complete, 1 runs
// missing, failed or not run within the budget, 3 only stage 2 of the plan left to run).
int do_study(const StudyArgs& a);

}  // namespace railcosim::cli
