// A run's judgement made from the measures of its own participants: the
// stability probe's parked run, the macro-step map (spectral.hpp), the
// matrix-free measure (matrix_free.hpp) and the defect check, each judged by
// the verdict (verdict/stability.hpp), then the errors against the reference
// (verdict/evaluation.hpp).
#pragma once

#include "cosim_case.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "verdict/stability.hpp"

namespace railcosim::run {

// The scene with the vehicle parked at its start and the probe's end time
// (verdict/stability.hpp: kProbeTime, kProbeMinSteps).
Scene parked_scene(const Scene& scene, double macro_step);

// Runs the probe for a co-simulation case with the run's options.
verdict::Stability probe_stability(const Scene& scene, const CaseSpec& spec,
                                   const RunOptions& options);

// The run's stability (unless `probe` is false: then its stability is
// verdict::kNotJudged, unless the defect grows along the run), then its
// judgement (verdict/evaluation.hpp): what `master run` and the study do for
// a co-simulation whose soil runs in the master. The verdict rests on the
// spectral radius of the macro-step map (spectral.hpp) where it can be
// computed, else on the probe; a defect that grows along the moving run
// makes it unstable too.
void assess(RunRecord& run, const RunRecord& reference, const Scene& scene, const CaseSpec& spec,
            const RunOptions& options, bool probe = true);
// Its first half: the stability verdict and the defect check, no errors.
void assess_growth(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                   const RunOptions& options, bool probe = true);

}  // namespace railcosim::run
