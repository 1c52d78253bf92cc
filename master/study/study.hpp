// The study of a scene: the monolithic reference and every co-simulation
// case, a sweep of macro steps for each method, the monolithic run across
// tolerances, then summary.csv, figures and REPORT.md. A study is a plan
// (study_plan.hpp), its runs executed here or by any engine that runs command
// lines, and the collection of their folders into one report.
#pragma once

#include <atomic>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cosim_case.hpp"
#include "engine/coupling_options.hpp"
#include "remote/transport_names.hpp"
#include "run/run_record.hpp"
#include "scene.hpp"

namespace railcosim::study {

// A co-simulation method: a case, its feedthrough and how it couples.
struct Method {
  CaseSpec spec;
  Feedthrough feedthrough = Feedthrough::kLagged;
  engine::CouplingOptions coupling;  // explicit with held inputs: the paper's methods
  // Multirate: a cut's window in macro steps H (e.g. {"ss", 5}); empty: one rate.
  std::map<std::string, long> cut_windows;
  // Case name, "-resolved" appended for the resolved variant,
  // "+implicit-linear-iqn-ils" or "+explicit-extrapolate1" for other couplings,
  // and "+ss-at-5H" for a cut at its own window.
  std::string label() const;
};

// Every case of the paper, and the resolved variant of each Jacobi X-T case
// (the only ones where the feedthrough changes anything).
std::vector<Method> all_methods();
// The same for every case a scene can run (case_names(scene)), and for each
// single-cut Jacobi case three more couplings: implicit with linear inputs and
// IQN-ILS, explicit with inputs extrapolated at first order, and implicit
// with cubic substep waveforms and IQN-ILS (implicit-waveform3-iqn-ils).
// Multirate: where the scene gives a cut a window (`[coupling]
// CUT_macro_step`, k H at the scene's H, k >= 2), each lagged method of a
// case with that cut once again with the cut at k H (at every H of the
// sweep).
std::vector<Method> methods_for(const Scene& scene);
// The cuts the scene gives a window of their own, with it in the scene's
// macro steps (integer multiples over one only).
std::map<std::string, long> scene_cut_windows(const Scene& scene);

// The methods of a study with nodes given ("ROLE=HOST:PORT" each): those
// whose participants include every given role (the others never reach the
// given node) and whose inputs are not substep waveforms (which the study runs
// in process, away from any node). Throws std::invalid_argument naming a
// malformed entry, or a role no method has (with the roles there are).
std::vector<Method> methods_with_nodes(const Scene& scene, const std::vector<Method>& methods,
                                       const std::vector<std::string>& nodes);

// The methods of a study of a scene whose soil the study starts itself
// (common/outside_soil.hpp: the FE soil, the Green's-function soil), as
// master run does: those whose inputs are not substep waveforms (run in
// process, where that soil is not) and, for a soil that takes the ballast
// force only, whose ss cut is X-T. Throws std::invalid_argument if none is.
// The methods of a study of a scene that maps a participant to an FMU (the
// vehicle's [vehicle.fmu], a soil FMU its [soil] table names): those whose
// cuts the FMU's mapping serves, held inputs unless the FMU follows input
// derivatives, no substep waveforms, implicit only where it saves its
// state. Each method left out is logged with the reason; throws
// std::invalid_argument if none is left.
std::vector<Method> methods_an_fmu_serves(const Scene& scene, const std::vector<Method>& methods);
// The macro steps of `sweep` the FMUs of `method`'s participants take: an
// FMU that cannot vary its communication step is held to its default
// experiment's step (logged). Throws std::invalid_argument, saying what to
// set, when none is left or the scene's own macro step is not that step.
std::vector<double> macro_steps_an_fmu_serves(const Scene& scene, const Method& method,
                                              const std::vector<double>& sweep);
// Both, where the scene maps a participant to an FMU; nothing otherwise.
void fit_to_fmus(const Scene& scene, std::vector<Method>& methods, std::vector<double>& sweep);
std::vector<Method> methods_with_started_soil(const Scene& scene,
                                              const std::vector<Method>& methods);

// The transport a study runs a coupling over: the study's, except for
// substep waveforms, which the study runs in process ("inproc").
std::string run_transport(const engine::CouplingOptions& coupling, const std::string& transport);

// --sweep KEY=V1,V2,...: a scene value (dotted TOML key) and its values.
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
};
// Throws std::invalid_argument saying what is wrong with the text.
SweepAxis parse_sweep(const std::string& text);

struct StudyOptions {
  std::filesystem::path out = "results";
  int jobs = 1;
  // The transport of the co-simulation runs.
  std::string transport = remote::kTcpTransport;
  std::vector<double> macro_steps;     // the sweep (each must divide t_end)
  std::vector<double> tolerances;      // of the monolithic reference curve
  double converged_tolerance = 1e-10;  // the reference all accuracies are measured against
  std::vector<Method> methods;         // empty: methods_for(scene)
  // Implicit methods are swept only from this H up (their accuracy at small
  // H is already reached at larger ones, at many times the cost); 0: all.
  double implicit_min_macro_step = 1e-4;
  // Runs the rail/sleepers X-X pair under both restart conventions to check
  // the paper's "almost 10" (paper scenes only: those with an rs cut).
  bool restart_check = true;
  std::vector<SweepAxis> sweeps;  // scene variants: the cartesian product of the axes
  std::string master_program;     // what the plan's command lines call; empty: this program
  std::string figure_script;      // empty: scripts/figures.py next to the sources
  const std::atomic<int>* stop = nullptr;  // a signal: the remaining runs fail at once
  // Participants served by nodes already running, "ROLE=HOST:PORT" each
  // (--node): the study keeps the methods whose every participant role is
  // given or built in, runs them over TCP one at a time, and judges each
  // against its co-simulation reference at the sweep's smallest macro step.
  std::vector<std::string> nodes;
  // The most the study may take, in seconds (0: no limit): a run not started
  // within it is written "not_run" with the reason, never left out.
  double budget_s = 0;
  // Case names (--cases): only the methods of these cases; empty: every case.
  std::vector<std::string> cases;
};

// One run of the study and where it stands.
struct StudyRun {
  // "case" (the scene's H), "sweep", "tolerance", "restart", "converged" (the
  // reference of rel_l2_error_converged) or "other-transport".
  std::string group;
  std::string folder;   // relative to the study's folder
  std::string variant;  // the swept scene values, "key=value;..." ("" without a sweep)
  std::string method;   // Method::label(), or "monolithic"
  double tolerance = 0;
  run::RunRecord record;              // status "missing" when the run left no readable summary.json
  double rel_l2_error_converged = 0;  // deflection at t_end against the converged reference
};

// Default sweep: 1e-5 ... 1e-3 s, kept to the steps that divide t_end.
std::vector<double> default_macro_steps(const Scene& scene);

// What the collection of a study's folder found.
struct CollectedStudy {
  std::vector<StudyRun> runs;  // in the plans' order
  int failed = 0, missing = 0;
  int not_run = 0;  // written "not_run": the study's budget was spent before they started
  // Stage 2 (the other-transport reruns) is planned in OUT/plan-2.txt but
  // none of its runs has been done yet.
  bool stage2_pending = false;
  bool complete() const { return failed == 0 && missing == 0 && not_run == 0 && !stage2_pending; }
};

// `master study --collect DIR`: reads DIR/plan.txt, DIR/plan-2.txt (written
// here once stage 1 is complete) and every run folder they name; writes
// DIR/summary.csv, the figures and DIR/REPORT.md. Throws for an unreadable
// plan or a file it cannot write (naming the file and the reason). With
// `write` false it only reads (and plans stage 2).
CollectedStudy collect_study(const std::filesystem::path& dir, const std::string& figure_script,
                             bool write = true);

// `master study`: the plan of `scene_path` (written to OUT/plan.txt), its runs
// here (--jobs workers, each with its own nodes), stage 2 the same way, then
// collect_study(). Throws only for what stops the whole study (an unwritable
// folder, nodes that cannot start); a run that fails is recorded as failed.
CollectedStudy run_study(const std::string& scene_path, const StudyOptions& options);
// Throws std::invalid_argument for a scene the study cannot run: an
// external soil, a soil the study starts (FE, Green's functions) over a
// transport that cannot reach it.
void check_study_scene(const Scene& scene, const StudyOptions& options);

// Whether a run has an error on the speed/accuracy chart: it ran to its end
// and, judged against a co-simulation reference, was measured against it.
bool charted(const run::RunRecord& r);

// Writes FILE: one row per run. Throws std::runtime_error naming the file
// and the reason when it cannot be written whole.
void write_summary_csv(const std::filesystem::path& file, const std::vector<StudyRun>& runs);

}  // namespace railcosim::study
