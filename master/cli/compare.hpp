// `master compare`: two runs' output folders, value by value (a column of names: equal), to a
// stated tolerance: the check that a participant of one's own computes what the built-in one does
// (docs/participant-guide-cpp.md, "Checking it").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace railcosim::cli {

// What `compare` reads of a folder it is given (someone else's, perhaps):
// a file's size (--max-file-mb, default kDefaultMaxFileMb), a line's length
// and a header's columns. Memory stays a few numbers per column, whatever
// the rows.
inline constexpr std::size_t kMaxCsvLineBytes = 4u << 20;
inline constexpr std::size_t kMaxCsvColumns = 65536;
inline constexpr double kDefaultMaxFileMb = 2048;

struct CompareArgs {
  CLI::App* command = nullptr;
  std::string reference, other;
  double tolerance = 1e-9;
  double max_file_mb = kDefaultMaxFileMb;
  bool check = false;
};

// Adds `compare` to the master's command line, filling `a`.
void add_compare_command(CLI::App& app, CompareArgs& a);
// Prints one line per file over the tolerance and a verdict; the exit
// status: 0 every value within the tolerance, 1 a difference (or a file,
// a run, a column or a row missing from the other folder).
int do_compare(const CompareArgs& a);

// The files of a run folder compared, where the reference has them.
const std::vector<std::string>& compared_files();

// The comparison of one file of one run.
struct FileComparison {
  std::string name;  // "wr-xx+ss-xx-jacobi/history.csv"
  std::string worst_column;
  double worst = 0;     // the largest difference of a column over its scale
  std::string problem;  // not empty: the file cannot be compared (missing, shape)
};

struct RunComparison {
  std::vector<FileComparison> files;
  double tolerance = 0;
  std::size_t runs = 0;
  // Whether every file compared and agreed within the tolerance.
  bool agree() const;
  // The file with the largest difference (nullptr when none compared).
  const FileComparison* worst() const;
};

// Compares the run folders under `reference` (a `master run --out` folder:
// one folder per case; or one run folder, holding history.csv) with those of
// the same names under `other`: every file of compared_files() the
// reference has must be in `other` with the same header and row count, and
// each column's largest difference, divided by the largest magnitude of
// that column in the reference (1 if all zero), is judged against
// `tolerance`. A non-finite value agrees only with the same one. Throws
// std::invalid_argument naming the folder or the file, line and column of
// what cannot be read (no runs, a value that is not a number), or refused:
// not a regular file (a FIFO is refused at once, not waited on), over
// `max_file_bytes`, a line over kMaxCsvLineBytes, a header over
// kMaxCsvColumns.
RunComparison compare_runs(const std::filesystem::path& reference,
                           const std::filesystem::path& other, double tolerance,
                           std::uintmax_t max_file_bytes);

}  // namespace railcosim::cli
