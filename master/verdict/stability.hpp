// Whether a coupling is stable, told apart from whether it is accurate: the
// growth measures' arithmetic and what the verdict makes of them.
//
// The size of a run's error against the monolithic run says how accurate a
// coupling is, not whether it is stable: a consistent first-order coupling at
// a large macro step can be far off and perfectly stable. Stability is a
// growth rate. The probe runs the same case, in process, with the vehicle
// parked at its start (speed 0) from the coupled static state, where the
// monolithic solution stays at rest: every deviation from that state is the
// coupling's own error, seeded by round-off. A stable coupling keeps it at
// round-off; an unstable one multiplies it by orders of magnitude. The run
// module makes the probe's run (run/assess.hpp); the verdict classifies it.
#pragma once

#include <string>
#include <vector>

#include "verdict/map_measure.hpp"
#include "verdict/run_record.hpp"

namespace railcosim::verdict {

struct Stability {
  bool unstable = false;
  double growth = 1;      // largest deviation over the last quarter / over the first
  double rate_per_s = 0;  // ln(growth) per second between the two quarters
  double duration_s = 0;  // the probe's length
  long steps = 0;         // its macro steps
};

// Deviations are relative to the static state; the first quarter's largest
// is taken as at least this round-off floor (explicit coupling), or as at
// least the convergence criterion of an implicit one, whose accepted
// iterates stand that far from the exact coupled step.
inline constexpr double kProbeFloor = 1e-13;
// Unstable: the deviation grows by more than this over the probe. A stable
// coupling stays within a factor of about 10 of round-off (measured on the
// paper scene), an unstable one grows by 1e5 to 1e17.
inline constexpr double kUnstableGrowth = 1e3;
// The probe lasts at least this long and at least kProbeMinSteps macro
// steps, at most the scene's end time.
inline constexpr double kProbeTime = 0.05;
inline constexpr long kProbeMinSteps = 100;

// Growth of a series of relative deviations sampled every dt seconds.
Stability classify_growth(const std::vector<double>& deviation, double dt,
                          double floor = kProbeFloor);

// The relative deviation from the first row of every channel of a run: the
// wheel, the contact force, the extra history channels and the coupling
// history; per row the largest over the channels that are non-zero at rest.
std::vector<double> deviation_from_rest(const RunRecord& run);

// A growth that e-folds within this many times the run's own duration makes
// a coupling unstable: rate >= 1 / (kGrowthHorizon t_end). Ten durations: a
// user runs the same coupling on a track ten times as long, and the growth
// of ten e-folds over it (2e4) ends it.
inline constexpr double kGrowthHorizon = 20;
// The rate at or above which the map's growth makes a run unstable, 1/s.
double unstable_rate(double t_end);

// The check over the moving run itself. The coupling's defect at each macro
// step: per coupling quantity (the wheel, the contact force, every further
// history channel, every cut's coupling history) the second difference
// |s(n+1) - 2 s(n) + s(n-1)|, which a held or extrapolated input misses and
// which an oscillating mode of the coupling carries, over the quantity's
// largest magnitude in the run; per row the largest over the quantities.
std::vector<double> coupling_defect(const RunRecord& run);
struct DefectGrowth {
  bool grows = false;
  double growth = 1;      // largest defect over the last eighth / over the eighths before
  double rate_per_s = 0;  // ln(growth) per eighth of the run, in 1/s
};
// Growing: the defect's largest value over the run's last eighth is at
// least kDefectGrowth times its largest over the eighths before it from the
// second quarter on (the first holds the start's transient). On the paper
// scene's study the stable runs keep it within 0.85 to 1.3; a growing mode of
// the coupling (rs-xt-gauss-seidel at H = 5e-4 s, which diverges at
// t = 0.43 s when the run goes on) triples it.
inline constexpr double kDefectGrowth = 2;
DefectGrowth defect_growth(const std::vector<double>& defect, double dt);

// The probe's verdict on its parked run `parked`, sampled every dt seconds:
// its deviation from rest classified against the round-off floor (an
// implicit coupling's: at least its `convergence`); a parked run that
// diverged is unstable.
Stability probe_growth(const RunRecord& parked, double dt, bool implicit, double convergence);

// The stability of a run whose participants the probe cannot build: one
// served by a node the user started (--node ROLE=HOST:PORT), which may run
// a model of its own behind the scene's name.
inline constexpr const char* kNotJudged = "not judged";

// The map's verdict on a run (the map of a case at rest, measured at
// `t_end`'s bound unstable_rate): its spectral radius where the measure
// converged. Arnoldi's converged eigenvalues are eigenvalues, not always the
// largest: a Krylov measure below the bound is kNotJudged, as is one that ran
// out of its budget. Returns true where the map's implicit steps did not
// converge (its note recorded): the probe judges the run then
// (judge_by_probe).
bool judge_by_map(RunRecord& run, const MapSpectrum& m, double t_end, bool implicit);
// The probe's verdict on a run.
void judge_by_probe(RunRecord& run, const Stability& s);
// The defect check over the moving run, sampled every dt seconds: recorded,
// and the run unstable when the defect grows.
void judge_defect(RunRecord& run, double dt);
// The stability of a run whose model the verdict cannot build (a node the
// user started may run a model of its own behind the scene's name): as
// measured through its participants already (matrix_free.hpp), else
// kNotJudged; then the defect check, which is the run's own. A failed run
// is left as it is.
void judge_without_model(RunRecord& run, double dt);

}  // namespace railcosim::verdict
