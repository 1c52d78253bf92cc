// The report's "error against H per input degree": for each case coupled
// implicitly with IQN-ILS, the error against the study's reference at
// each macro step H of the sweep, per kind of inputs (linear, waveform0..3),
// and the slope of log(error) against log(H) fitted by least squares.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "study/study.hpp"

namespace railcosim::study {

struct SlopeRow {
  std::string case_name;                          // "rs-xx-jacobi"
  std::string inputs;                             // "linear", "waveform3", ...
  std::vector<std::pair<double, double>> errors;  // (H, rel_l2_error_converged), ascending H
  std::optional<double> slope;                    // from 2 points up
  // Macro steps of runs left out of the fit: judged against a co-simulation
  // reference at their own H, their error is the reference's round-off.
  std::vector<double> left_out;
};

// The least-squares slope of log(y) against log(x); nullopt below 2 points
// or when every x is the same. Every value must be > 0.
std::optional<double> log_log_slope(const std::vector<std::pair<double, double>>& xy);

// One row per (case, inputs) among the implicit IQN-ILS runs of the "case"
// and "sweep" groups that ran to the end with an error above 0, in the
// order the runs name the cases, inputs ordered hold, linear, waveform0..3.
std::vector<SlopeRow> error_slopes(const std::vector<StudyRun>& runs);

// error_slopes.csv: case,inputs,points,slope,h_min_s,h_max_s. Throws naming the file.
void write_slopes_csv(const std::filesystem::path& file, const std::vector<SlopeRow>& rows);

// The section "Error against H per input degree", headed at level `h`
// (nothing when there are no rows).
// `against` names what the errors are measured against (reference_words()).
void write_slopes_section(std::ostream& md, const std::vector<SlopeRow>& rows, const std::string& h,
                          const std::string& against);

}  // namespace railcosim::study
