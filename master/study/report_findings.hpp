// The paper's findings as data: one row per finding (report_findings_table.cpp),
// each evaluated by check_findings (report_findings.cpp) with the measure
// function its row names.
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "study/report.hpp"

namespace railcosim::study {

// What a measure function sees: the study's runs, and the runs at the
// scene's macro step by method label (every paper case is there).
struct FindingRuns {
  const std::vector<StudyRun>& runs;
  std::map<std::string, const run::RunRecord*> cases;
  std::vector<Method> methods;  // the paper's cases
};

// Two runs compared: `name` as the evidence calls the pair, then the runs.
struct RunPair {
  std::string name;
  std::string first;
  std::string second;
};

// A finding's verdict and evidence, as a measure function finds them.
struct Measured {
  std::string verdict;
  std::string evidence;
};

struct FindingRow;
using FindingMeasure = Measured (*)(const FindingRow& row, const FindingRuns& in);

// One of the paper's findings: its statement, what the paper found, the
// runs it compares and how, and the tolerance its verdict is judged with.
struct FindingRow {
  std::string claim{};   // the paper's statement
  std::string paper{};   // what the paper found (its number, where it gives one)
  std::string judged{};  // the tolerance, as the report states it
  FindingMeasure measure = nullptr;
  std::vector<std::string> runs{};   // the runs (or cuts) the measure reads, in its order
  std::vector<RunPair> pairs{};      // the pairs of runs it compares
  std::vector<std::string> sides{};  // how the evidence names the compared runs
  int lower = 0;                     // which run of a pair the paper finds more accurate (0, 1)
  std::string counted{};             // what the pairs are, after "N of M"
  double paper_value = NAN;          // the paper's number
  double tolerance = 0;  // a factor around it, or pairs that may go the other way for "partly"
  std::string note{};    // said when the pair named `note_pair` goes the other way
  std::string note_pair{};
};

// The rows, in the order the report lists them.
extern const std::vector<FindingRow> kFindingTable;

// The measure functions the rows use.
Measured amplified_and_biggest(const FindingRow& row, const FindingRuns& in);
Measured history_error_between(const FindingRow& row, const FindingRuns& in);
Measured error_ratio(const FindingRow& row, const FindingRuns& in);
Measured lower_error_in_pairs(const FindingRow& row, const FindingRuns& in);
Measured fewer_unstable_runs(const FindingRow& row, const FindingRuns& in);
Measured stable_and_below_factor(const FindingRow& row, const FindingRuns& in);

}  // namespace railcosim::study
