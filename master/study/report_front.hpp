// The study's answer: per cut, the cheapest run reaching each accuracy level
// against the converged reference. One definition, written to front.csv,
// printed at the top of REPORT.md and drawn by scripts/figures.py.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "remote/transport_names.hpp"
#include "study/study.hpp"

namespace railcosim::study {

// One row of front.csv. `cut` is "wr", "rs", "ss", "wr+ss", ..., or
// "monolithic" for the monolithic tolerance sweep (the reference).
struct FrontRow {
  std::string cut;
  // The transport of its candidates: the study's, or "inproc" for the runs
  // of a TCP study that it runs in process only (substep waveforms), which
  // form rows of their own: their wall times have no network to pay.
  std::string transport;
  double level = 0;               // error at most (rel. L2 against the converged run)
  const StudyRun* run = nullptr;  // the cheapest run reaching it; null: none
};

// The cut of a method label: "wr-xt-jacobi+implicit-..." -> "wr",
// "wr-xx+ss-xt-jacobi" -> "wr+ss", "monolithic" -> "monolithic".
std::string cut_of(const std::string& method);

// Per cut (in the order the runs name them, "monolithic" last), per
// transport (the study's `transport` first, then "inproc" where the cut has
// co-simulation runs in process in a TCP study) and per accuracy level: among
// the runs of the "case" and "sweep" groups over that transport (the
// "tolerance", "case" and "converged" monolithic runs for "monolithic") that
// end `ok` with rel_l2_error_converged <= level, the one with the least wall
// time (the first in plan order on a tie).
std::vector<FrontRow> study_front(const std::vector<StudyRun>& runs,
                                  const std::string& transport = remote::kTcpTransport);

// The column of a front row in the report: "wr cut", "wr cut, in process"
// (a row over another transport than the study's), "monolithic (no cut)".
std::string front_column(const FrontRow& row, const std::string& transport);

// front.csv: cut,level,method,macro_step_s,tolerance_m,wall_s,error,transport,folder
// (empty method: no run reaches the level; its transport is then the
// row's). Throws naming the file.
void write_front_csv(const std::filesystem::path& file, const std::vector<FrontRow>& front);

// The report's opening answer: per cut, one line with the method to use at
// each level and its cost.
void write_answer(std::ostream& md, const std::vector<FrontRow>& front,
                  const std::string& transport);

// "Cheapest method per accuracy": the front as a table, with the wall time
// of the same method and H over the other transport where stage 2 ran it.
void write_front_table(std::ostream& md, const std::vector<FrontRow>& front,
                       const std::vector<StudyRun>& runs, const std::string& transport,
                       const std::string& h);

}  // namespace railcosim::study
