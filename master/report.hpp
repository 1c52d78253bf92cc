// REPORT.md of a study, and its figures (drawn by scripts/figures.py with
// matplotlib when it is there).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "study.hpp"

namespace railcosim {

// One of the paper's conclusions, checked against this study's runs.
struct Finding {
  Finding(std::string claim_, std::string verdict_, std::string evidence_)
      : claim(std::move(claim_)), verdict(std::move(verdict_)), evidence(std::move(evidence_)) {}
  std::string claim;     // as the paper puts it
  std::string verdict;   // "reproduced", "partly reproduced", "not reproduced", "not checked"
  std::string evidence;  // ours: the numbers that say so
  std::string paper;     // what the paper found (its number, where it gives one)
  std::string judged;    // the tolerance the verdict is judged with
};

std::vector<Finding> check_findings(const std::vector<StudyRun>& runs);

// Draws the figures (if it can) and writes DIR/REPORT.md.
void write_report(const Scene& scene, const StudyOptions& options,
                  const std::vector<StudyRun>& runs, const RunRecord& converged);

}  // namespace railcosim
