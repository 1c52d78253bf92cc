// The scene's [coupling] table under the command line of `master run`: each
// key the scene sets stands in for its flag unless the flag was given.
#pragma once

#include <string>

#include "cli/cli_run.hpp"
#include "scene.hpp"

namespace railcosim::cli {

// `a` with every key of the scene's [coupling] whose flag was not given on
// the command line (a.command tells which were).
RunArgs with_scene_coupling(const RunArgs& a, const Scene& scene);

// "" when the scene set nothing the run takes; otherwise "; the scene's
// [coupling] (FILE) set: inputs = "linear", ..." for an error message.
std::string scene_coupling_note(const RunArgs& a, const Scene& scene);

}  // namespace railcosim::cli
