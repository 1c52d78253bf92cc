// REPORT.md of a study, and its figures (drawn by scripts/figures.py with
// matplotlib when it is there).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "remote/transport_names.hpp"
#include "study/study.hpp"

namespace railcosim::study {

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

// What the report says about the study as a whole (from its plan).
struct StudyReportInfo {
  std::filesystem::path dir;  // the study's folder: scene.toml, run folders
  std::string source_scene;   // the user's scene file
  std::string transport = remote::kTcpTransport;
  double converged_tolerance = 1e-10;
  std::vector<SweepAxis> sweeps;
  // Each scene variant's label ("key=value;...") and folder, in plan order;
  // one ("", "") without a sweep.
  std::vector<std::pair<std::string, std::string>> variants;
  std::string figure_script;  // empty: scripts/figures.py next to the sources
  bool stage1_complete = true;
  bool stage2_pending = false;  // the other-transport reruns are planned, not done
};

// Draws the figures (if it can; one set per scene variant, from a
// summary.csv of its own in its folder) and writes DIR/REPORT.md, its tables
// grouped by scene variant. Throws std::runtime_error naming the file and
// the reason when a file cannot be written.
void write_report(const StudyReportInfo& info, const std::vector<StudyRun>& runs);

}  // namespace railcosim::study
