// The conformance kit's statics direction check (docs/protocol.md §16): the
// case's coupled static state found as a run finds it, with the subject as
// the soil and the master's own models as the other participants; at that
// state the soil must sink under the vehicle's weight, and a lumped soil's
// springs must carry it: k_f Σ s_i = m·g within kStaticsTolerance of m·g
// (k_f the scene's [soil] stiffness, s_i the soil's displacements, positive
// down). A soil of another model (k_f unknown here) is held to the sign:
// Σ s_i > 0.
#pragma once

#include <string>

#include "cli/conform.hpp"
#include "scene.hpp"

namespace railcosim::cli {

constexpr double kStaticsTolerance = 1e-6;

// "" when the check holds, "skipped: ..." when the subject is not the
// case's soil, else what the soil carries against m·g.
std::string check_soil_statics(const Scene& scene, const ConformOptions& o);

}  // namespace railcosim::cli
