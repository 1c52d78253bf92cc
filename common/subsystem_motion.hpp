// The motion inside a built-in Subsystem's snapshot (Subsystem::save()):
// the displacements, velocities and accelerations of its degrees of
// freedom, read and replaced in place, so that a snapshot perturbed along
// one coordinate can be restored. For the linearised macro-step map of a
// coupling (master/run/spectral.hpp); a snapshot that is not a subsystem's
// is refused with BadInputError.
#pragma once

#include <vector>

#include "participant.hpp"

namespace railcosim {

// u, then v, then a: 3n values for n degrees of freedom.
std::vector<double> snapshot_motion(const ParticipantState& state);
// Replaces them; `motion` must have as many values as snapshot_motion().
void set_snapshot_motion(ParticipantState& state, const std::vector<double>& motion);

}  // namespace railcosim
