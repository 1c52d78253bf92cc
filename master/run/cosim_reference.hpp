// The co-simulation reference of a run (verdict/reference.hpp) made from
// the run's own participants: the same case run Jacobi, implicit and
// converged, at H_ref and 2 H_ref, by the participants `make` makes over
// the run's transport; the verdict judges the run against it.
#pragma once

#include <string>

#include "cosim_case.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "verdict/reference.hpp"

namespace railcosim::run {

// Judges a run of `spec` at options.macro_step against its co-simulation
// reference at `reference_step` (verdict::assess_against_reference: which
// macro step, and when the run is not judged), its runs made from
// participants made by `make` over `transport`. With `shared`, the
// reference runs are made once for every run asking for the same ones, and
// written below its root.
void assess_against_cosim(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                          const RunOptions& options, const remote::ParticipantFactory& make,
                          const std::string& transport, double reference_step,
                          verdict::CosimReferences* shared = nullptr);

}  // namespace railcosim::run
