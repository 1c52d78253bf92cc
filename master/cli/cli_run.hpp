// `master run`: its options and the run of one case.
#pragma once

#include "engine/coupling_options.hpp"
#include "engine/cut_windows.hpp"
#include "remote/transport_names.hpp"

#include <map>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace railcosim::cli {

struct RunArgs {
  CLI::App* command = nullptr;
  std::string scene_path;
  std::string case_name;
  double macro_step = 0;  // 0: from the scene
  // --macro-step CUT=H_cut: the cuts given their own window on the command line
  std::map<std::string, engine::CutWindow> cut_windows;
  double tolerance = 0;  // 0: from the scene
  std::string feedthrough = "lagged";
  std::string restart;  // empty: from the scene
  std::string transport = remote::kTcpTransport;
  std::string vehicle, track;
  std::vector<std::string> nodes;  // ROLE=HOST:PORT
  std::string out = "results";
  std::string token_file;
  std::string coupling = "explicit", inputs = "hold", accelerator = "iqn-ils";
  std::string data_plane = "direct";
  long window_steps = 0;
  double step_budget = 120;        // s
  double step_deadline_floor = 2;  // s: the least a silent macro step is waited for
  double reference_step = 0;       // s; 0: half the macro step (verdict/reference.hpp)
  std::string judge = "full";      // what the verdict measures (run::JudgeMode)
  double judge_budget = 1.0;       // Arnoldi's products over the run's macro steps
  engine::CouplingOptions c;       // the numbers; the names above are parsed into it
  bool check = false;              // master --check: stop once everything is read and checked
};

// Adds --judge and --judge-budget to `run` (judge_options.cpp).
void add_judge_options(CLI::App* run, RunArgs& a);
// Adds `run` to the master's command line, filling `a`.
void add_run_command(CLI::App& app, RunArgs& a);
// Runs the case; the exit status (0 finished, 1 failed; usage errors throw).
int do_run(const RunArgs& a);

}  // namespace railcosim::cli
