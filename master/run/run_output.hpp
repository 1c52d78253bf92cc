// Writes a run's files in DIR/CASE/: deflection.csv, history.csv,
// summary.json, and with the scene's channels soil.csv, soil_forces.csv
// (the ballast_force_* channels, one column per sleeper, not repeated in
// history.csv) and spectra.csv (one-third-octave bands of the contact
// forces and the ballast forces). Each file is written beside its final name and renamed, so a
// reader never sees half a file.
#pragma once

#include <cstdio>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "run/block_writer.hpp"
#include "run/run_record.hpp"

namespace railcosim::run {

// Writes `text` beside `path` (PATH.part) and renames it into place. Every
// write is checked: on failure the .part file is removed and
// std::runtime_error names the path and the reason ("No space left on
// device").
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

// Room kept for summary.json while a run writes its history (bytes).
inline constexpr std::size_t kSummaryReserve = 8192;

// Returns the folder written. Throws std::runtime_error naming the path.
std::filesystem::path write_run(const std::filesystem::path& out_dir, const RunRecord& run);

// Writes a run as it goes: history.csv grows in blocks (BlockWriter: up to
// 1024 rows or 100 ms of rows per write), deflection.csv and summary.json
// come at the end. A run that fails still leaves its history so far (every
// row, flushed by finish() or the destructor) and a summary.json saying why
// and how many history rows the file holds; a master killed outright loses
// at most the last block.
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
  // Data rows (not the header) history.csv holds so far.
  long history_rows() const;

 private:
  std::filesystem::path dir_;
  std::unique_ptr<BlockWriter> history_;
  std::vector<std::string> extra_;
  std::vector<bool> in_history_;  // per extra channel: written to history.csv
  bool header_written_ = false;
  void header();
  // Appends to history.csv (a block at a time); throws naming the reason.
  void put(const std::string& text);
};

// A string as a JSON string, quoted and escaped.
std::string json_quoted(const std::string& text);
std::string summary_json(const RunRecord& run);
// The judgement's parts of summary.json, each line "  \"key\": {...},\n":
// the stability (verdict/stability.hpp) and what the run was judged against
// (verdict/evaluation.hpp); and the first alone, "\"stability\": {...}" (no
// trailing comma).
std::string judgement_json(const RunRecord& run);
std::string stability_json(const RunRecord& run);

// soil_forces.csv: a row per communication point, `t_s` then the force into
// the ballast under each sleeper (N, positive down), the columns headed by
// the sleepers' positions x in metres. Empty when the run has none.
std::string soil_forces_csv(const RunRecord& run);
// spectra.csv: long format, one row per signal and band:
// signal,band,centre_Hz,lower_Hz,upper_Hz,rms,level_dB (level re 1 N). The
// signals: contact_force_N, force_wK_N per wheel, ballast_force_I_N per
// sleeper. Bands from twice the record's lowest frequency to its Nyquist
// frequency. Empty when the run is too short (fewer than 16 rows).
std::string spectra_csv(const RunRecord& run);

// The shortest text that reads back to the same double ("null" if not finite).
std::string format_double(double v);

// Scientific notation with the given digits after the point, e.g. 1.23e-04:
// how the reports print errors and times.
inline std::string sci(double v, int digits = 2) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*e", digits, v);
  return buf;
}

}  // namespace railcosim::run
