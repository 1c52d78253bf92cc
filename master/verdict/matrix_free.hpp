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
// The measure's arithmetic (the perturbation, the passes' difference, the
// slope fit) and what it says of a run are here; the model is seen only
// through its passes (CouplingPasses), which the run module makes from the
// parked participants wherever they live (run/matrix_free.hpp).
//
// How far it can be trusted (measured over TCP against the dense map of
// run/spectral.hpp, tests/matrix_free_test.cpp): where the dominant mode is
// separated in modulus from the rest, its rate agrees with the dense one
// to 2 % (rs-xx-jacobi at H = 1e-3 s: rho = 1.055, 54 /s); where the
// lightly damped structural modes lead (|lambda| within about 1e-3 of 1)
// it measures their slow decay only to about 1 / (the steps taken), so
// growths slower than that (the paper scene's rho = 1.0000229 at 5e-5 s)
// are beyond it. The participants take the micro steps they take: the dense
// map fixes the count of the step at rest, and so must the scene (its
// simulation.micro_steps) for the two to describe the same map.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "verdict/run_record.hpp"

namespace railcosim::verdict {

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

// How the measure takes a coupling: an implicit one converged tightly
// (kMatrixFreeConvergence), with a larger perturbation (its iterates stand
// that far apart) that may grow less before it leaves the linear range.
struct MatrixFreeSettings {
  double size = kMatrixFreePerturbation;
  double growth = kMatrixFreeGrowth;
  bool implicit = false;
};
MatrixFreeSettings matrix_free_settings(bool implicit);

// The model's side of the measure: the coupling data the master holds in
// the parked co-simulation at rest (each participant's outputs at t_n, in
// one fixed order), the kind of each, and passes from that saved state.
struct CouplingPasses {
  enum class Kind { kDisplacement, kVelocity, kForce };
  std::vector<double> rest;
  std::vector<Kind> kinds;
  // One pass from the saved state at rest with the coupling data `start`
  // (an implicit coupling's first step in one pass, unconverged, so that
  // the perturbation reaches the participants' inner states): `after_step`
  // is called with the coupling data after each macro step and returns
  // whether to go on; the pass also ends where a step fails (the
  // perturbation ran away) or after the most steps the model takes.
  std::function<void(const std::vector<double>& start,
                     const std::function<bool(const std::vector<double>&)>& after_step)>
      pass;
};

// The estimate through the passes of a coupling at macro step H whose map
// steps span `window` seconds (a multirate plan's slow window).
MatrixFreeRho measure_matrix_free(const CouplingPasses& passes, const MatrixFreeSettings& settings,
                                  double H, double window);

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

// The measure's steps for a run of t_end seconds at macro step H whose map
// steps span `ratio` macro steps.
long matrix_free_steps(double t_end, double H, long ratio);

// A run's stability from the matrix-free measure (a run that ran to its
// end): unstable, on the basis "matrix-free", when the perturbation grew at
// a rate of at least unstable_rate(t_end) and either kMatrixFreeGrowth times
// (implicit: kMatrixFreeImplicitGrowth) or kMatrixFreeLateGrowth times from
// the second quarter of the steps taken to the last; otherwise the verdict is left as it is
// (growths too slow to double within the parked steps are not resolved:
// matrix_free_rho and its steps are recorded all the same). A measure that
// fails leaves its reason in spectral_note (add_matrix_free_note), and so
// does an implicit one whose perturbation did not reach the participants'
// inner states (carried below kMatrixFreeCarried): nothing is recorded.
void judge_matrix_free(RunRecord& run, const MatrixFreeRho& m, const MatrixFreeSettings& settings,
                       double t_end);
// Adds to the record's note on rho (the map's, where it could not be built).
void add_matrix_free_note(RunRecord& run, const std::string& note);

}  // namespace railcosim::verdict
