// The macro-step map of a co-simulation's own participants, linearised at
// the coupled static state: built here as a linear operator and measured by
// the verdict (verdict/map_measure.hpp, verdict/spectrum.hpp).
//
// With the vehicle parked at its start (speed 0) the coupled static state is
// a fixed point of the co-simulation's macro step. Near it the step is a
// linear map z -> A z of the whole coupled state: every participant's motion
// (displacements, velocities, accelerations of its degrees of freedom) and
// the master's part (each participant's outputs at t_n, and the points
// before them for extrapolated inputs).
//
// A is applied through the product's own step: the coupled state is
// perturbed by +e v and -e v from the static state, one macro step is taken
// with the case's schedule, and the central difference of the stepped
// states is the product (the Hertz contact is the one non-linearity;
// central differences leave an error of order e^2). The coordinates are
// scaled by their perturbations (a diagonal similarity, which leaves the
// eigenvalues as they are); the dense measure drops the coordinates the step
// ignores (zero columns: the accelerations under a consistent restart),
// whose eigenvalues are 0.
//
// The map takes the micro steps the parked step takes (one per macro step
// under the adaptive control, or the scene's fixed count); a moving run may
// take more, and then the label describes the parked coupling, which the
// run's own defect check (verdict/stability.hpp) complements.
#pragma once

#include <Eigen/Core>

#include "cosim_case.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "verdict/map_measure.hpp"

namespace railcosim::run {

// The spectral radius of the case's macro-step map under these options, its
// participants the built-in subsystems made in the master's process (for a
// run over TCP: the same subsystems the node programs serve). An implicit
// coupling's step is the fixed point its iterations converge to: each of
// its steps is iterated to kMapConvergence, and the map is not computed
// where a step does not get there.
verdict::MapSpectrum macro_step_spectrum(const Scene& scene, const CaseSpec& spec,
                                         const RunOptions& options,
                                         const verdict::MapSettings& settings = {});

// The same map's matrix, column by column (what the dense measure takes
// whole): for the benchmarks and the tests that hold solvers against it.
Eigen::MatrixXd macro_step_matrix(const Scene& scene, const CaseSpec& spec,
                                  const RunOptions& options);

}  // namespace railcosim::run
