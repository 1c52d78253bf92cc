// How a co-simulation run is judged against the monolithic reference.
#pragma once

#include "run_record.hpp"
#include "scene.hpp"

namespace railcosim {

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

// The bound beyond which a displacement means divergence:
// divergence_factor times the largest static displacement.
double divergence_bound(const Scene& scene, double largest_static_displacement);

// Fills the errors and the status (ok / amplified) of a finished run.
void judge(RunRecord& run, const RunRecord& reference, const Scene& scene);

}  // namespace railcosim
