// Writes a run's files in DIR/CASE/: deflection.csv, history.csv and
// summary.json. Each file is written beside its final name and renamed, so a
// reader never sees half a file.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "run_record.hpp"

namespace railcosim {

// Writes `text` beside `path` (PATH.part) and renames it into place. Every
// write is checked: on failure the .part file is removed and
// std::runtime_error names the path and the reason ("No space left on
// device").
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

// Room kept for summary.json while a run writes its history (bytes).
inline constexpr std::size_t kSummaryReserve = 8192;

// Returns the folder written. Throws std::runtime_error naming the path.
std::filesystem::path write_run(const std::filesystem::path& out_dir, const RunRecord& run);

// Writes a run as it goes: history.csv grows (and is flushed) with every
// row, deflection.csv and summary.json come at the end. A run that fails
// still leaves its history so far and a summary.json saying why.
class RunWriter {
 public:
  // Creates OUT/FOLDER/ (FOLDER is the case name for `master run`), reserves
  // room for summary.json and starts history.csv. Throws std::runtime_error.
  // row() throws, naming the reason, once the history cannot be written.
  RunWriter(const std::filesystem::path& out_dir, const std::string& folder);
  ~RunWriter();
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;
  // The names of the history channels beyond the wheel's (before the first row).
  void channels(const std::vector<std::string>& extra);
  void row(const HistoryRow& row);
  // Writes deflection.csv (if the run has one) and summary.json. A file that
  // cannot be written makes the summary say the run failed and why; then
  // throws std::runtime_error with that reason (after the summary, if even
  // that could be written).
  void finish(const RunRecord& run);
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::FILE* history_ = nullptr;
  std::vector<std::string> extra_;
  bool header_written_ = false;
  bool wrote_history_ = false;  // some of history.csv reached the disk
  void header();
  // Appends to history.csv and flushes; throws naming the reason.
  void put(const std::string& text);
};

std::string summary_json(const RunRecord& run);

// The shortest text that reads back to the same double ("null" if not finite).
std::string format_double(double v);

}  // namespace railcosim
