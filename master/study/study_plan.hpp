// The plan of a study: every run as one complete `master run` command line,
// after a header with the study's settings. Any engine that runs command
// lines (GNU parallel, a Slurm job array, a Kubernetes job) can execute it;
// `master study --collect` gathers the run folders afterwards. docs/study.md,
// "Plans and clusters", documents the format:
//
//   # ...                       comments, for people
//   #% key = value              one study setting per line
//   master run ARGS #% folder=F group=G method=M case=C macro_step=H tolerance=T
//                      variant=V variant_dir=D
//
// A run line is a shell command; everything after " #% " is a shell comment
// that tells the collection step what the run is. Format 1; a reader refuses
// any other.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cosim_case.hpp"
#include "engine/coupling_options.hpp"
#include "study/study.hpp"

namespace railcosim::study {

constexpr int kPlanFormat = 1;

// One run. `master run --out OUT/PREFIX --case CASE` writes OUT/PREFIX/CASE/,
// so folder always ends in the case name.
struct PlannedRun {
  std::string folder;       // relative to the study's folder
  std::string group;        // case, sweep, restart, tolerance, converged, other-transport
  std::string method;       // Method::label(), or "monolithic"
  std::string variant;      // swept values "key=value;key=value" ("" without a sweep)
  std::string variant_dir;  // its folder ("" without a sweep)
  std::string scene;        // the scene file, relative to the study's folder
  std::string case_name;
  Feedthrough feedthrough = Feedthrough::kLagged;
  engine::CouplingOptions coupling;
  std::string transport;  // of a co-simulation run
  double macro_step = 0;
  double tolerance = 0;
  // Every cut of the case the scene or the method gives a window of its own,
  // in macro steps (1: at H): `--macro-step CUT=k*H`, so that the run's
  // rates are the method's whatever the scene's defaults.
  std::map<std::string, long> cut_windows;
  // With nodes given: the macro step of the co-simulation reference (the
  // sweep's smallest); 0: none asked.
  double reference_step = 0;
};

struct StudyPlan {
  int format = kPlanFormat;
  int stage = 1;                                // 2: the other-transport reruns
  std::filesystem::path out;                    // the study's folder, as the command lines name it
  std::string source_scene;                     // the user's scene file
  std::string master;                           // the program the command lines call
  std::string transport;                        // of the study's co-simulation runs
  std::vector<double> macro_steps, tolerances;  // as asked (empty macro_steps: the default)
  double converged_tolerance = 1e-10;
  std::vector<SweepAxis> sweeps;
  // Nodes already running, "ROLE=HOST:PORT" each (--node of every
  // co-simulation run; a plan with nodes has no stage 2).
  std::vector<std::string> nodes;
  std::vector<PlannedRun> runs;
  // Scene files the runs read, relative to `out`, and their text.
  std::vector<std::pair<std::string, std::string>> scene_files;
};

// Builds the plan of `master study` for the scene file and options: the
// scene copied to scene.toml, a scene variant per point of the sweeps
// (cartesian product), a variant with 10 fixed micro steps per restart
// convention. Throws std::invalid_argument for an unknown or untyped --sweep
// key (naming it) or a macro step that does not divide a variant's end time,
// SceneError for a value the scene refuses.
StudyPlan make_plan(const std::string& scene_path, const StudyOptions& options);

// Stage 2: the cheapest method reaching each accuracy level (per scene
// variant) of the collected stage-1 runs, again over the other transport.
StudyPlan other_transport_plan(const StudyPlan& stage1, const std::vector<StudyRun>& runs);

// The `master run` command of one run (without the trailing comment).
std::string command_line(const StudyPlan& plan, const PlannedRun& run);
std::string plan_text(const StudyPlan& plan);

// The plan's file in the study's folder: OUT/plan.txt, OUT/plan-2.txt.
std::filesystem::path plan_file(const std::filesystem::path& out, int stage);

// Writes the scene files, the plan to OUT/plan[-2].txt and, if `copy` is not
// empty and another file, to `copy`. Throws std::runtime_error naming the
// file and the reason.
void write_plan(const StudyPlan& plan, const std::filesystem::path& copy = {});

// Reads a plan back (the runs' folder, group, method, case, macro step,
// tolerance and variant); throws std::invalid_argument naming file and line.
StudyPlan read_plan(const std::filesystem::path& file);

}  // namespace railcosim::study
