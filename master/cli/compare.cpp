#include "cli/compare.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace railcosim::cli {
namespace fs = std::filesystem;

const std::vector<std::string>& compared_files() {
  static const std::vector<std::string> files{"deflection.csv", "history.csv", "soil.csv",
                                              "soil_forces.csv"};
  return files;
}

bool RunComparison::agree() const {
  return std::all_of(files.begin(), files.end(), [&](const FileComparison& f) {
    return f.problem.empty() && f.worst <= tolerance;
  });
}

const FileComparison* RunComparison::worst() const {
  const FileComparison* w = nullptr;
  for (const FileComparison& f : files)
    if (f.problem.empty() && (!w || !(f.worst <= w->worst))) w = &f;
  return w;
}

namespace {

// A CSV file read line by line through a bounded buffer: only a regular
// file (a FIFO or a device is refused before a byte is read, without
// waiting for a writer), of at most `max_bytes`, its lines at most
// kMaxCsvLineBytes long.
class CsvFile {
 public:
  CsvFile(const fs::path& path, std::uintmax_t max_bytes) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd_ < 0) throw std::invalid_argument(path.string() + ": cannot be read");
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd_);
      throw std::invalid_argument(path.string() +
                                  ": not a regular file (a FIFO, a device or a folder): refused");
    }
    if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
      ::close(fd_);
      throw std::invalid_argument(path.string() + ": " + std::to_string(st.st_size) +
                                  " bytes, over the bound of " + std::to_string(max_bytes) +
                                  " bytes (--max-file-mb)");
    }
    left_ = max_bytes;
  }
  ~CsvFile() { ::close(fd_); }
  CsvFile(const CsvFile&) = delete;
  CsvFile& operator=(const CsvFile&) = delete;

  // The next line (without its newline) into `line`, and its number; false
  // at the end of the file.
  bool next(std::string& line) {
    line.clear();
    bool any = false;
    while (true) {
      if (at_ == size_ && !fill()) {
        if (any) ++number_;
        return any;
      }
      any = true;
      const char* from = buf_.data() + at_;
      const char* nl = static_cast<const char*>(std::memchr(from, '\n', size_ - at_));
      const std::size_t take = nl ? static_cast<std::size_t>(nl - from) : size_ - at_;
      if (line.size() + take > kMaxCsvLineBytes)
        throw std::invalid_argument(path_.string() + ":" + std::to_string(number_ + 1) +
                                    ": a line over " + std::to_string(kMaxCsvLineBytes) +
                                    " bytes: refused");
      line.append(from, take);
      at_ += take;
      if (nl) {
        ++at_;
        ++number_;
        return true;
      }
    }
  }
  long number() const { return number_; }
  const fs::path& path() const { return path_; }

 private:
  bool fill() {
    // The file may grow after fstat: the bound holds for what is read.
    if (left_ == 0)
      throw std::invalid_argument(path_.string() +
                                  ": grew past the bound while read (--max-file-mb)");
    const ssize_t n = ::read(fd_, buf_.data(), std::min<std::uintmax_t>(buf_.size(), left_));
    if (n < 0) throw std::invalid_argument(path_.string() + ": cannot be read");
    at_ = 0;
    size_ = static_cast<std::size_t>(n);
    left_ -= size_;
    return n > 0;
  }
  fs::path path_;
  int fd_ = -1;
  std::array<char, 65536> buf_{};
  std::size_t at_ = 0, size_ = 0;
  std::uintmax_t left_ = 0;
  long number_ = 0;
};

void split(const std::string& line, std::vector<std::string>& cells) {
  cells.clear();
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = line.find(',', from);
    cells.push_back(line.substr(from, comma - from));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  if (line.empty()) cells.clear();
}

bool parse_number(const std::string& cell, double& v) {
  char* end = nullptr;
  v = std::strtod(cell.c_str(), &end);
  return !cell.empty() && end == cell.c_str() + cell.size();
}

// One column of both files as they are read: kept as a few numbers, not
// as its cells. A column of the reference that is not all numbers is a
// column of names (equal or not).
struct Column {
  bool numbers = true;  // every reference cell so far a number
  bool equal = true;    // every cell so far the same text
  double scale = 0, diff = 0;
  // The other's first cell that is not a number (at most 40 bytes of it) and its line (0: none).
  long not_number_line = 0;
  std::string not_number;
  void take(const std::string& a, const std::string& b, const CsvFile& other) {
    equal = equal && a == b;
    double x = 0, y = 0;
    if (!numbers || !parse_number(a, x)) {
      numbers = false;
      return;
    }
    if (!parse_number(b, y)) {
      if (not_number_line == 0) {
        not_number_line = other.number();
        not_number = b.substr(0, 40);
      }
      return;
    }
    if (std::isfinite(x)) scale = std::max(scale, std::abs(x));
    const bool same = x == y || (std::isnan(x) && std::isnan(y));
    const double d = same ? 0.0 : std::abs(x - y);
    diff = std::isnan(d) || std::isinf(d) ? INFINITY : std::max(diff, d);
  }
  // The largest difference over the reference's largest magnitude.
  double difference() const {
    if (!numbers) return equal ? 0.0 : INFINITY;
    return diff / (scale > 0 ? scale : 1.0);
  }
};

// The header of `f`, within kMaxCsvColumns.
std::vector<std::string> header_of(CsvFile& f) {
  std::string line;
  if (!f.next(line)) throw std::invalid_argument(f.path().string() + ": empty");
  if (static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) >= kMaxCsvColumns)
    throw std::invalid_argument(f.path().string() + ":1: over " + std::to_string(kMaxCsvColumns) +
                                " columns: refused");
  std::vector<std::string> header;
  split(line, header);
  return header;
}

// The next row of `f` into `cells`, as many as the header's; false at the end.
bool row_of(CsvFile& f, std::string& line, std::vector<std::string>& cells, std::size_t columns) {
  if (!f.next(line)) return false;
  split(line, cells);
  if (cells.size() != columns)
    throw std::invalid_argument(f.path().string() + ":" + std::to_string(f.number()) + ": " +
                                std::to_string(cells.size()) + " values, the header has " +
                                std::to_string(columns));
  return true;
}

FileComparison compare_file(const fs::path& reference, const fs::path& other,
                            const std::string& name, std::uintmax_t max_bytes) {
  FileComparison f;
  f.name = name;
  if (!fs::exists(fs::symlink_status(other))) {
    f.problem = "missing from " + other.parent_path().string();
    return f;
  }
  CsvFile a(reference, max_bytes), b(other, max_bytes);
  const std::vector<std::string> header = header_of(a);
  if (header != header_of(b)) {
    f.problem = "the header differs";
    return f;
  }
  std::vector<Column> columns(header.size());
  std::string line;
  std::vector<std::string> x, y;
  std::size_t rows_a = 0, rows_b = 0;
  while (true) {
    const bool more_a = row_of(a, line, x, header.size());
    const bool more_b = row_of(b, line, y, header.size());
    rows_a += more_a;
    rows_b += more_b;
    if (!more_a || !more_b) {
      while (more_a && row_of(a, line, x, header.size())) ++rows_a;
      while (more_b && row_of(b, line, y, header.size())) ++rows_b;
      break;
    }
    for (std::size_t c = 0; c < header.size(); ++c) columns[c].take(x[c], y[c], b);
  }
  if (rows_a != rows_b) {
    f.problem = std::to_string(rows_a) + " rows, the other " + std::to_string(rows_b);
    return f;
  }
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (columns[c].numbers && columns[c].not_number_line > 0)
      throw std::invalid_argument(other.string() + ":" +
                                  std::to_string(columns[c].not_number_line) + ": column " +
                                  header[c] + ": '" + columns[c].not_number + "' is not a number");
    const double d = columns[c].difference();
    if (f.worst_column.empty() || !(d <= f.worst)) {
      f.worst = d;
      f.worst_column = header[c];
    }
  }
  return f;
}

// The run folders under `root` (or `root` itself, a run folder), by name.
std::vector<std::string> run_names(const fs::path& root) {
  if (!fs::is_directory(root)) throw std::invalid_argument(root.string() + ": not a folder");
  if (fs::exists(root / "history.csv")) return {""};
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(root))
    if (entry.is_directory() && fs::exists(entry.path() / "history.csv"))
      names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  if (names.empty())
    throw std::invalid_argument(root.string() +
                                ": no runs (neither history.csv nor folders holding one)");
  return names;
}

}  // namespace

RunComparison compare_runs(const fs::path& reference, const fs::path& other, double tolerance,
                           std::uintmax_t max_file_bytes) {
  RunComparison r;
  r.tolerance = tolerance;
  if (!fs::is_directory(other)) throw std::invalid_argument(other.string() + ": not a folder");
  for (const std::string& run : run_names(reference)) {
    ++r.runs;
    for (const std::string& file : compared_files()) {
      const fs::path a = reference / run / file;
      if (!fs::exists(a)) continue;
      const std::string name = run.empty() ? file : run + "/" + file;
      r.files.push_back(compare_file(a, other / run / file, name, max_file_bytes));
    }
  }
  return r;
}

}  // namespace railcosim::cli
