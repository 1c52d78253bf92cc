// REPORT.md of a study, and its figures (drawn by scripts/figures.py with
// matplotlib when it is there).
#pragma once

#include <string>
#include <vector>

#include "study.hpp"

namespace railcosim {

// One of the paper's conclusions, checked against this study's runs.
struct Finding {
  std::string claim;     // as the paper puts it
  std::string verdict;   // "reproduced", "partly reproduced", "not reproduced", "not checked"
  std::string evidence;  // the numbers that say so
};

std::vector<Finding> check_findings(const std::vector<StudyRun>& runs);

// Draws the figures (if it can) and writes DIR/REPORT.md.
void write_report(const Scene& scene, const StudyOptions& options,
                  const std::vector<StudyRun>& runs, const RunRecord& converged);

}  // namespace railcosim
