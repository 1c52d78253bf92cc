// Everything one run produces: what summary.json, deflection.csv and
// history.csv hold, and what the verdict judges. The run module (run/)
// fills it; the verdict reads it and sets its judgement's fields.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/convergence.hpp"
#include "participant.hpp"
#include "remote/transport_names.hpp"

namespace railcosim::verdict {

struct RunRecord {
  std::string case_name;
  std::optional<std::string> split, coupling, scheme, feedthrough;  // none for monolithic
  double macro_step = 0;
  double t_end = 0;  // the end time asked for
  double wall_s = 0;
  long macro_steps = 0;  // done
  // Data rows history.csv holds, when it was written as the run went (a
  // failed run's may be fewer than `history`); else history.size().
  std::optional<long> history_rows;
  std::map<std::string, long>
      micro_steps;  // per subsystem ("monolithic", or "s1", "s2", ... in load order)
  // Every cut of a co-simulation case and its window (s): H, or a multiple
  // of it (multirate); none for the monolithic run.
  std::map<std::string, double> windows;
  // ok; inaccurate (stable, error over the scene's bounds); amplified (the
  // coupling makes a perturbation grow: stability.hpp); diverged;
  // not_converged; not_judged (no reference to measure its error against:
  // reference.hpp); failed.
  std::string status = "ok";
  std::string message;                                  // why, when not ok
  std::optional<double> max_abs_error_m, rel_l2_error;  // none when not comparable
  std::optional<double> history_error;
  // The stability probe (stability.hpp): "stable" or "unstable", empty when
  // it did not run; the growth factor of a perturbation of the static state,
  // its rate (1/s) and the probe's length (s).
  std::string stability;
  std::optional<double> error_growth, error_growth_rate, probe_time;
  // What the verdict rests on: "map" (the spectral radius of the linearised
  // macro-step map, map_measure.hpp), "probe", or "" when not judged.
  std::string stability_basis;
  // The map: its spectral radius rho, ln(rho) / H (1/s), its coordinates
  // and the seconds it took; or why it was not computed.
  std::optional<double> spectral_radius, spectral_rate, map_seconds;
  std::optional<long> map_dimension;
  // How the map was measured: "krylov" (Arnoldi, the default) or "dense"
  // (the test oracle), and the products of the map it took (each two
  // parked macro steps).
  std::string map_method;
  std::string map_solver;  // the eigen-solver that ran (Spectrum::solver)
  std::optional<long> map_products;
  std::optional<long> map_micro_steps;  // per macro step, the most of a participant
  std::string spectral_note;
  // The growth rate measured through the participants (matrix_free.hpp):
  // its rho, its rate ln(rho) / H per second and the parked macro steps it
  // took; the verdict's basis "matrix-free" when it found a clear growth.
  std::optional<double> matrix_free_rho, matrix_free_rate;
  std::optional<long> matrix_free_steps;
  // The check over the moving run (stability.hpp): the growth of the
  // coupling's defect between the second and the last quarter, its rate
  // (1/s), and whether it says the run grows.
  std::optional<double> defect_growth, defect_rate;
  bool defect_grows = false;
  // What the errors are measured against: "monolithic", "co-simulation"
  // (reference.hpp: its macro step, coupling and Richardson estimates
  // of its own history and deflection errors), "none", or "" (not judged).
  std::string reference_kind, reference_coupling, reference_note;
  // Where a study wrote the co-simulation reference (its finer run), relative
  // to the study's folder; "" where it was not written.
  std::string reference_folder;
  std::optional<int> reference_order;  // of the Richardson estimate (reference.hpp)
  std::optional<double> reference_macro_step, reference_history_error, reference_rel_l2_error;
  std::string transport = remote::kInprocTransport;
  std::string data_plane;              // over TCP: "direct" or "relay"
  std::string data_plane_mode;         // direct: "windows" or "lock step"
  std::string restart = "consistent";  // at communication points: consistent or carry
  // How the macro step was coupled (coupling_options.hpp): explicit or
  // implicit, hold/linear/extrapolate1/extrapolate2, and the accelerator.
  std::string method = "explicit", inputs = "hold";
  std::optional<std::string> accelerator;  // implicit only
  // Implicit runs: iterations per macro step and the convergence log.
  std::optional<double> iterations_mean;
  std::optional<long> iterations_max, not_converged_steps;
  std::vector<std::string> convergence_quantities;
  using ConvergenceRow = engine::ConvergenceRow;  // engine/convergence.hpp
  std::vector<ConvergenceRow> convergence;

  std::vector<double> x;           // rail node positions
  std::vector<double> deflection;  // rail node displacements at the last time
  std::vector<HistoryRow> history;
  // Per linear cut ("rs", "ss"): the largest displacement of its lower side
  // over the coupling points, one value per history row (run/coupling_history.hpp).
  std::map<std::string, std::vector<double>> coupling_history;
  std::vector<std::string> extra_channels;  // names of HistoryRow::extra, e.g. "soil_peak_m"
  std::vector<double> soil;                 // soil mass displacements at the last time, if any
  std::vector<double> soil_x;               // their positions (under the sleepers)
  std::vector<double> sleeper_x;            // positions of the ballast_force_* channels, if any
};

// The spectral radius a run's verdict measured: the map's, else the one
// measured through the participants (matrix_free.hpp); its growth rate per
// second; and which of the two it is ("map", "matrix-free", "" for none).
inline std::optional<double> rho_of(const RunRecord& r) {
  return r.spectral_radius ? r.spectral_radius : r.matrix_free_rho;
}
inline std::optional<double> rho_rate_of(const RunRecord& r) {
  return r.spectral_radius ? r.spectral_rate : r.matrix_free_rate;
}
inline std::string rho_basis_of(const RunRecord& r) {
  if (r.spectral_radius) return r.stability_basis == "matrix-free" ? "matrix-free" : "map";
  return r.matrix_free_rho ? "matrix-free" : "";
}

// A run that ran to its end and was judged: its errors against the
// monolithic run are comparable (ok, inaccurate or amplified).
inline bool ran_to_end(const RunRecord& r) {
  return r.status == "ok" || r.status == "inaccurate" || r.status == "amplified";
}

}  // namespace railcosim::verdict
