// The stability of a coupling as a number: the spectral radius of its
// macro-step map, linearised at the coupled static state.
//
// With the vehicle parked at its start (speed 0) the coupled static state is
// a fixed point of the co-simulation's macro step. Near it the step is a
// linear map z -> A z of the whole coupled state: every participant's motion
// (displacements, velocities, accelerations of its degrees of freedom) and
// the master's part (each participant's outputs at t_n, and the points
// before them for extrapolated inputs). A perturbation grows when the
// spectral radius rho of A is over 1, at the rate ln(rho) / H per second.
//
// A is built column by column through the product's own step: the coupled
// state is perturbed along each coordinate by +e and -e from the static
// state, one macro step is taken with the case's schedule, and the central
// difference of the stepped states is the column (the Hertz contact is the
// one non-linearity; central differences leave an error of order e^2). The
// coordinates are scaled by their perturbations (a diagonal similarity,
// which leaves the eigenvalues as they are), coordinates the step ignores
// (zero columns: the accelerations under a consistent restart) are dropped
// (their eigenvalues are 0), and every eigenvalue of the rest is computed
// densely (Eigen's real Schur form). Plain power iteration would not do:
// the lightly damped structural modes of the track sit at |lambda| close to
// 1 and hide a growth of 1 + 2e-5 per step.
//
// The map takes the micro steps the parked step takes (one per macro step
// under the adaptive control, or the scene's fixed count); a moving run may
// take more, and then the label describes the parked coupling, which the
// run's own defect check (stability.hpp) complements.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

#include "cosim_case.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "verdict/spectrum.hpp"

namespace railcosim::run {

struct MapSpectrum {
  bool computed = false;
  double rho = 0;           // the largest modulus of an eigenvalue of the map
  double rate_per_s = 0;    // ln(rho) / H: the growth rate of its mode, 1/s
  double frequency_hz = 0;  // its mode's frequency: |arg(lambda)| / (2 pi H)
  long dimension = 0;       // the coordinates of the map (dense: after dropping the ignored)
  long products = 0;        // products of the map taken (each two parked macro steps)
  std::string method;       // "krylov" or "dense"
  long states = 0;          // the coupled state's coordinates before that
  long micro_steps = 0;     // the micro steps of its macro step (the most of a participant)
  double seconds = 0;       // the wall time of the computation
  std::string why_not;      // when not computed: why
  std::vector<std::complex<double>> leading;  // the eigenvalues found, largest first
};

// The relative size of the perturbations: of the static displacements and
// forces (1e-6 of the largest).
inline constexpr double kMapPerturbation = 1e-6;
// Implicit coupling: each step of the map is iterated to this residual
// (relative to the static values), in at most kMapMaxIterations iterations.
inline constexpr double kMapConvergence = 1e-12;
inline constexpr int kMapMaxIterations = 200;

// The spectral radius of the case's macro-step map under these options, its
// participants the built-in subsystems made in the master's process (for a
// run over TCP: the same subsystems the node programs serve). An implicit
// coupling's step is the fixed point its iterations converge to: each of
// its steps is iterated to kMapConvergence, and the map is not computed
// where a step does not get there.
enum class MapMethod {
  // The dense map up to kDenseMapLimit coordinates, Arnoldi above: the default.
  kAuto,
  // The dominant eigenvalues by Arnoldi's method (verdict/spectrum.hpp):
  // O(N k) memory and a number of products that does not grow with N; on a
  // spectrum crowded along the unit circle (the lightly damped track modes
  // of the paper scene: moduli 2e-6 apart) it does not converge within any
  // affordable budget, and the verdict then says "not judged".
  kKrylov,
  // Every column and every eigenvalue (LAPACK's multishift QR): exact, O(N^2) memory and
  // O(N^3) work; the oracle of the tests and the measure of small models.
  kDense,
};
// The largest map the default measures densely: 4000 coordinates before the
// step's ignored ones are dropped. The shipped scenes' maps (636 to 1209)
// take a few tenths of a second; the dense eigen-solve's O(N^3) work passes
// the run's own time well before the limit (155 sleepers, 2,176 coordinates
// kept: about 10 s against a run of half a second), which keeps the models
// the tests and studies judge exactly; above it (600 sleepers: 11,409)
// Arnoldi's method within its budget.
inline constexpr long kDenseMapLimit = 4000;
struct MapSettings {
  MapMethod method = MapMethod::kAuto;
  verdict::Budget budget;
  verdict::KrylovSettings krylov;
};
MapSpectrum macro_step_spectrum(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                                const MapSettings& settings = {});

// The same map's matrix, column by column (what the dense measure takes
// whole): for the benchmarks and the tests that hold solvers against it.
Eigen::MatrixXd macro_step_matrix(const Scene& scene, const CaseSpec& spec,
                                  const RunOptions& options);

}  // namespace railcosim::run
