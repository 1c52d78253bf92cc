// The checks a scene passes beyond each key's own range (common/scene.cpp):
// integers that fit before they are converted, numbers the model's
// arithmetic can carry, and the derived quantities every run needs (the load,
// the static deflection, the mesh against the nodes' limits, the memory of
// the history) — all before anything runs, on the file path and on the wire
// path alike (a node rebuilds its scene through Scene::validate()).
#pragma once

#include <cstdint>
#include <string>

namespace railcosim {

struct Scene;

// The largest mesh a node (and the master's monolithic reference) accepts:
// about 100,000 DOFs at two elements per span; the band matrices and their
// cached factorisations then take some hundreds of MB at most.
inline constexpr int kMaxSleepers = 20000;
inline constexpr int kMaxElementsPerSpan = 16;
// Macro steps of one run: the master keeps every history row in memory
// (some 50 bytes each, more with many channels), so 10^6 steps are some 50 MB.
inline constexpr long kMaxMacroSteps = 1'000'000;
// Micro steps of a whole run when the scene fixes them (macro steps x
// simulation.micro_steps): about 100 s of the paper's track on one core at
// the measured 6 us per micro step. Adaptive runs are bounded per macro step
// by the node's --max-micro-steps instead.
inline constexpr double kMaxFixedMicroSteps = 16'777'216.0;
// The smallest micro-step tolerance, relative to the static deflection under
// the load: below it the error estimate is round-off (double precision,
// 16 digits, on displacements of that size) and no step size meets it.
inline constexpr double kMinRelativeTolerance = 1e-12;
// A random rail profile is laid on a grid along the wheels' path: at most
// this many grid points (two arrays of doubles: 64 MiB), and at most this many
// grid points x spectral components (the work of laying it: about a second).
inline constexpr double kMaxProfilePoints = 4'194'304.0;
inline constexpr double kMaxProfileWork = 2e8;
// A rail profile deeper or higher than this anywhere (m): a rail is 0.17 m
// high, and a wheel lifted by more than its flange leaves the model's range.
inline constexpr double kMaxProfileDepth = 0.1;
// A CSV rail profile file is read whole: at most this many bytes.
inline constexpr long kMaxProfileFileBytes = 64L * 1024 * 1024;
// Every non-zero number of a scene lies within this magnitude window: the
// model multiplies and divides a handful of them (mass over the square of a
// micro step, stiffness over the cube of an element length, ...), and values
// outside it make those products overflow to infinity or vanish, so the run
// would give NaN. Every physical value of a railway lies far inside it.
inline constexpr double kSmallestMagnitude = 1e-30;
inline constexpr double kLargestMagnitude = 1e30;
// The stiffnesses of the layers (and the rail's bending stiffness per
// element), and the masses, that the same matrices add up lie within this
// factor of each other, and a damper over one macro step within it of its
// layer's stiffness: beyond it the small terms fall below the rounding of the
// large ones (double precision: 16 digits) and the matrices turn singular or
// indefinite. The paper's track spans a factor 60 in stiffness and 750 in mass.
inline constexpr double kMaxSpread = 1e8;

// What is wrong with an integer of a scene file that is meant for an int
// ("" when it fits): checked before the conversion, so 2^32 + 50 sleepers is
// an error, not 50.
std::string integer_range_error(std::int64_t value);

// Every number of the scene inside the magnitude window. Throws SceneError
// naming the file and key. Called first by Scene::validate().
void check_scene_numbers(const Scene& scene);
// The derived quantities. Throws SceneError naming the file and the key to
// change. Called last by Scene::validate().
void check_scene_derived(const Scene& scene);

}  // namespace railcosim
