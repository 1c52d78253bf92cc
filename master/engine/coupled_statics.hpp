// The coupled static state, found through the interfaces alone (the way an
// outside participant can take part): each participant solves only its own
// static problem for the interface values it is given, and the master
// iterates over the interfaces until they agree.
#pragma once

#include <vector>

#include "engine/schedule.hpp"
#include "participant.hpp"
#include "scene.hpp"

namespace railcosim::engine {

struct StaticsOptions {
  // Relative change of each exchanged quantity (2-norm over every interface)
  // below which the iteration has converged; a few hundred ulps, so that the
  // static state matches a global solution to far better than 1e-9.
  double tolerance = 1e-13;
  // A finer mesh solves each participant's statics less exactly (the rail
  // elements' stiffness grows as the cube of their count per span), and the
  // change stalls above `tolerance` at round-off: the iteration is then
  // accepted once the change has not halved in `stall_iterations` and is
  // below `floor_tolerance` (16 elements per span stall near 2e-12).
  double floor_tolerance = 1e-9;
  int stall_iterations = 20;
  int max_iterations = 1000;
};

struct StaticsOutcome {
  std::vector<CouplingData> inputs;  // per participant: its inputs at the static state
  int iterations = 0;
  double residual = 0;  // the largest relative change of the last iteration
};

// Zero-valued inputs of the right shape for a participant.
CouplingData zero_inputs(const Scene& scene, const ParticipantSpec& participant);

// Block Gauss–Seidel over the participants: the sweep of a Gauss–Seidel step
// plan (step_plan.hpp), whose iterated links (the values that flow up the
// load path, from a later participant to an earlier one) are relaxed with
// Aitken's dynamic factor. Throws std::runtime_error if it does not
// converge, naming the residual and the iteration count.
StaticsOutcome find_static_state(const std::vector<Participant*>& participants,
                                 const Routing& routing, std::vector<CouplingData> inputs,
                                 const StaticsOptions& options = {});

}  // namespace railcosim::engine
