// The matrix-free growth rate (verdict/matrix_free.hpp) measured through a
// case's participants themselves, wherever they live (in process, on nodes
// over TCP, on the Python SDK): no matrix, only the participants' own save
// and restore. Here the parked co-simulation (parked.hpp) is brought to
// rest, and its passes, restored from the saved state with the coupling
// data the verdict moves, are handed to the verdict's measure.
#pragma once

#include <string>

#include "cosim_case.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "verdict/matrix_free.hpp"

namespace railcosim::run {

// The estimate for a co-simulation case under these options (explicit or
// implicit coupling, any inputs), its participants made over `transport` (a
// name of the transport table) with `setup` for the parked scene, over at
// most `max_steps` macro steps.
verdict::MatrixFreeRho matrix_free_rho(const Scene& scene, const CaseSpec& spec,
                                       const RunOptions& options, const std::string& transport,
                                       const remote::TransportSetup& setup, long max_steps);

// A run's stability from the matrix-free measure (a run that ran to its
// end; verdict::judge_matrix_free says what the verdict makes of it), over
// verdict::matrix_free_steps parked macro steps. A measure that fails leaves
// its reason in spectral_note.
void judge_growth_matrix_free(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                              const RunOptions& options, const std::string& transport,
                              const remote::TransportSetup& setup);

}  // namespace railcosim::run
