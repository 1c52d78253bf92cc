// How a co-simulation run is judged against its reference: the monolithic
// run, or the co-simulation reference (reference.hpp).
#pragma once

#include <string>
#include <vector>

#include "participant.hpp"
#include "scene.hpp"
#include "verdict/run_record.hpp"

namespace railcosim::verdict {

struct DeflectionError {
  double max_abs = 0;  // max_k |w_k - w_k,ref|, m
  double rel_l2 = 0;   // ||w - w_ref||_2 / ||w_ref||_2
};
DeflectionError deflection_error(const std::vector<double>& w, const std::vector<double>& ref);

// The RMS, over the common rows of the two histories, of the contact force
// error divided by the static load m_tot g, combined with the wheel
// displacement error divided by the static wheel displacement:
//   sqrt(mean(((F - F_ref) / (m g))^2 + ((q - q_ref) / q_static)^2)).
// Unlike the deflection at t_end, whose error depends on the phase of an
// oscillation at that instant, this sees a coupling that feeds energy into the
// system at any time of the run.
double history_error(const std::vector<HistoryRow>& h, const std::vector<HistoryRow>& ref,
                     double static_load, double static_wheel);

// The history error over every coupling quantity of a run: the wheel's two
// channels, every further history channel (soil_peak_m, per-wheel and
// ballast forces) and every linear cut of the run (RunRecord::coupling_history,
// which the run records as it goes),
// each error divided by the largest magnitude of that quantity (or of its
// family: all wheels, all sleepers) in the reference run. The result is the
// largest RMS over the quantities, the contact force and the wheel counted
// together as one.
double coupling_history_error(const RunRecord& run, const RunRecord& reference);

// A run whose deflection at t_end is further than this from the monolithic
// one (relative L2) is never `ok`: 25 %, six times the largest error of a
// consistent case of the paper scene at its macro step (4.3e-2, rs-xx-jacobi).
inline constexpr double kMaxDeflectionError = 0.25;

// A history error above this is an instability whatever the stability probe
// says: an RMS error as large as the static quantities themselves (the wheel
// leaves the rail and hits it again). On the paper scene's study a stable,
// consistent coupling stays at or below 0.22 (rs-xx-jacobi, H = 1e-3 s);
// the couplings the probe finds unstable reach 1.07 to 3.5; three whose
// probe stays at round-off but whose wheel bounces (wr-xt at H = 1e-3 s)
// reach 17 to 27.
inline constexpr double kGrossHistoryError = 1.0;

// The bound beyond which a displacement means divergence:
// divergence_factor times the largest static displacement.
double divergence_bound(const Scene& scene, double largest_static_displacement);

// A spectral radius with three digits in its distance from 1 (at least
// four in all): 1.0000229, 1.0113, 6.214.
std::string rho_words(double rho);

// Fills the errors and the status of a finished run. Its size: the history
// error over every coupling quantity against cosim.amplification_threshold,
// the deflection error against kMaxDeflectionError. Its growth: the run's
// stability probe (stability.hpp), when it ran. Status amplified when the
// probe found the coupling unstable or the history error is over
// kGrossHistoryError (then the stability is set to unstable too);
// inaccurate when it is stable (or was not probed) and an error is over its
// bound; ok otherwise. A diverged,
// failed or not_converged run keeps its status (the last with the rest
// added to its message).
void judge(RunRecord& run, const RunRecord& reference, const Scene& scene);

// The judgement of a run with no reference to measure its errors against
// (`why` says why not): amplified when its stability is unstable, else
// "not_judged" (a not_converged run keeps its status, `why` added); a
// diverged or failed run keeps its status.
void judge_unmeasured(RunRecord& run, const std::string& why);

}  // namespace railcosim::verdict
