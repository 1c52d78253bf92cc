// The growth rate of a coupling measured through its participants
// themselves, wherever they live (in process, on nodes over TCP, on the
// Python SDK): no matrix, only the participants' own save and restore.
//
// With the vehicle parked (vehicle.speed_kmh = 0, set in the scene's text,
// so that nodes are sent the scene they step) the coupled static state is a
// fixed point of the macro step. From it, after two macro steps, every
// participant is saved (save()) with the master's coupling memory. The
// co-simulation is then stepped twice from that saved state: once as it
// is, once with the coupling data the master holds (each participant's
// outputs at t_n) moved by kMatrixFreePerturbation of their static
// magnitudes, in a fixed pattern of signs. The difference of the two
// passes' coupling data, each coordinate over its perturbation, is the
// perturbation carried by the macro-step map through every participant's
// inner state; its norm grows like rho^n once the dominant mode leads. rho
// is the exponential of the least-squares slope of ln(norm) against n over
// the second half of the steps taken (the first half lets the other modes
// fall behind): a power iteration whose iterate is never renormalised. It
// ends when the perturbation has grown kMatrixFreeGrowth times, when the
// unperturbed pass has drifted kMatrixFreeDrift from rest (an unstable
// coupling grows from round-off too), or after the most steps asked for;
// both passes stay in the linear range of the Hertz contact.
//
// How far it can be trusted (measured over TCP against the dense map of
// spectral.hpp, tests/matrix_free_test.cpp): where the dominant mode is
// separated in modulus from the rest, its rate agrees with the dense one
// to 2 % (rs-xx-jacobi at H = 1e-3 s: rho = 1.055, 54 /s); where the
// lightly damped structural modes lead (|lambda| within about 1e-3 of 1)
// it measures their slow decay only to about 1 / (the steps taken), so
// growths slower than that (the paper scene's rho = 1.0000229 at 5e-5 s)
// are beyond it. The participants take the micro steps they take: the dense
// map fixes the count of the step at rest, and so must the scene (its
// simulation.micro_steps) for the two to describe the same map.
#pragma once

#include <string>

#include "cosim_case.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene.hpp"

namespace railcosim::run {

// The perturbation of the coupling data, relative to their static values.
inline constexpr double kMatrixFreePerturbation = 1e-9;
// The perturbation's growth at which the iteration ends.
inline constexpr double kMatrixFreeGrowth = 1e6;
// Implicit coupling (converged to kMatrixFreeConvergence, at most
// kMatrixFreeMaxIterations a step): the perturbation, and the growth that
// ends the iteration (its product stays 1e-3 of the static values, in the
// linear range).
inline constexpr double kMatrixFreeConvergence = 1e-10;
inline constexpr int kMatrixFreeMaxIterations = 100;
inline constexpr double kMatrixFreeImplicitPerturbation = 1e-7;
inline constexpr double kMatrixFreeImplicitGrowth = 1e4;
// Below this share of itself after the first step (which an implicit pass
// takes as one pass, unconverged, to carry the perturbation into the
// participants' inner states) the perturbation did not enter the map:
// nothing is measured.
inline constexpr double kMatrixFreeCarried = 1e-2;
// The unperturbed pass's largest drift from rest (relative to the static
// values) at which the iteration ends.
inline constexpr double kMatrixFreeDrift = 1e-3;

struct MatrixFreeRho {
  double rho = 0;          // exp(slope): the growth per macro step
  double rate_per_s = 0;   // ln(rho) / H
  long steps = 0;          // macro steps measured (each pass)
  double growth = 1;       // the perturbation's growth over them
  double carried = 0;      // its size after the first step, over its size at the start
  double late_growth = 0;  // its largest value over the last quarter of the steps taken
                           // over its largest over the second quarter
};

// The estimate for a co-simulation case under these options (explicit or
// implicit coupling, any inputs), its participants made over `transport` (a name of the
// transport table) with `setup` for the parked scene, over at most
// `max_steps` macro steps.
MatrixFreeRho matrix_free_rho(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                              const std::string& transport, const remote::TransportSetup& setup,
                              long max_steps);

// The parked macro steps a run's measure takes: kMatrixFreeRunLengths times
// its own count (a growth must have time to show), at most
// kMatrixFreeMaxSteps.
inline constexpr long kMatrixFreeMaxSteps = 2000;
inline constexpr long kMatrixFreeRunLengths = 10;
// A perturbation whose largest value over the last quarter of the steps
// taken is this many times its largest over the second quarter is growing:
// modes that do not grow have a falling envelope, and their beats reach it
// within a quarter.
inline constexpr double kMatrixFreeLateGrowth = 2.0;

// A run's stability from the matrix-free measure (a run that ran to its
// end): unstable, on the basis "matrix-free", when the perturbation grew at
// a rate of at least unstable_rate(t_end) and either kMatrixFreeGrowth times
// (implicit: kMatrixFreeImplicitGrowth) or kMatrixFreeLateGrowth times from
// the second quarter of the steps taken to the last; otherwise the verdict is left as it is
// (growths too slow to double within the parked steps are not resolved:
// matrix_free_rho and its steps are recorded all the same). A measure that
// fails leaves its reason in spectral_note.
void judge_growth_matrix_free(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                              const RunOptions& options, const std::string& transport,
                              const remote::TransportSetup& setup);

}  // namespace railcosim::run
