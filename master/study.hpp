// The study of a scene: the monolithic reference and every co-simulation
// case, a sweep of macro steps for each method, the monolithic run across
// tolerances, then summary.csv, figures and REPORT.md.
#pragma once

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "cosim_case.hpp"
#include "coupling_options.hpp"
#include "run_record.hpp"
#include "scene.hpp"

namespace railcosim {

// A co-simulation method: a case, its feedthrough and how it couples.
struct Method {
  CaseSpec spec;
  Feedthrough feedthrough = Feedthrough::kLagged;
  CouplingOptions coupling;  // explicit with held inputs: the paper's methods
  // Case name, "-resolved" appended for the resolved variant, and
  // "+implicit-linear-iqn-ils" or "+explicit-extrapolate1" for other couplings.
  std::string label() const;
};

// Every case of the paper, and the resolved variant of each Jacobi X-T case
// (the only ones where the feedthrough changes anything).
std::vector<Method> all_methods();
// The same for every case a scene can run (case_names(scene)), and for each
// single-cut Jacobi case two more couplings: implicit with linear inputs and
// IQN-ILS, and explicit with inputs extrapolated at first order.
std::vector<Method> methods_for(const Scene& scene);

struct StudyOptions {
  std::filesystem::path out = "results";
  int jobs = 1;
  std::string transport = "tcp";       // for the co-simulation runs
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
  std::string figure_script;               // empty: scripts/figures.py next to the sources
  const std::atomic<int>* stop = nullptr;  // a signal: the remaining runs fail at once
};

// One run of the study and where it stands.
struct StudyRun {
  std::string
      group;  // "case" (the scene's H), "sweep", "tolerance", "restart" or "other-transport"
  std::string folder;  // relative to the study's folder
  std::string method;  // Method::label(), or "monolithic"
  double tolerance = 0;
  RunRecord record;
  double rel_l2_error_converged = 0;  // deflection at t_end against the converged reference
};

// Default sweep: 1e-5 ... 1e-3 s, kept to the steps that divide t_end.
std::vector<double> default_macro_steps(const Scene& scene);

// Runs everything, writes every file; returns the runs. Throws only for what
// stops the whole study (an unwritable folder, nodes that cannot start); a run
// that fails is recorded as failed and the study goes on.
std::vector<StudyRun> run_study(const Scene& scene, const StudyOptions& options);

// Writes DIR/summary.csv: one row per run.
void write_summary_csv(const std::filesystem::path& file, const std::vector<StudyRun>& runs);

}  // namespace railcosim
