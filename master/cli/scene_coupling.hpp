// The scene's [coupling] table under the command line of `master run`: each
// key the scene sets stands in for its flag unless the flag was given.
#pragma once

#include <string>

#include "cli/cli_run.hpp"
#include "cosim_case.hpp"
#include "scene.hpp"

namespace railcosim::cli {

// `a` with every key of the scene's [coupling] whose flag was not given on
// the command line (a.command tells which were).
RunArgs with_scene_coupling(const RunArgs& a, const Scene& scene);

// "" when the scene set nothing the run takes; otherwise "; the scene's
// [coupling] (FILE) set: inputs = "linear", ..." for an error message.
std::string scene_coupling_note(const RunArgs& a, const Scene& scene);

// The window of each cut of the case as a count of finest windows H: from
// --macro-step CUT=H_cut, else the scene's [coupling] CUT_macro_step, else 1.
// Throws std::invalid_argument naming the option when a window given on the
// command line is for a cut the case does not have, is no integer multiple
// of H, or is finer than H. The scene's windows are defaults: one applies
// where the case has its cut and it is an integer multiple of H over one;
// elsewhere the cut exchanges every H.
std::map<std::string, long> check_cut_windows(const RunArgs& a, const Scene& scene,
                                              const CaseSpec& spec, double finest);
// --macro-step H (the finest window) and --macro-step CUT=H_cut, repeatable.
void add_macro_step_option(CLI::App& run_command, RunArgs& a);

// Where the cuts' windows came from, for a message ("--macro-step ss=0.001").
std::string cut_windows_note(const RunArgs& a, const Scene& scene);

// The footer of `master run --help`: every key of [coupling] with the flag
// it stands in for, from the same table the run takes them by.
std::string scene_coupling_help();

}  // namespace railcosim::cli
