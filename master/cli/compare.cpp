#include "cli/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
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

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> cells;  // per column
  std::size_t rows = 0;
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// A CSV file: a header and rows of as many cells.
Table read_table(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path.string() + ": cannot be read");
  Table t;
  std::string line;
  if (!std::getline(in, line)) throw std::invalid_argument(path.string() + ": empty");
  t.header = split(line);
  t.cells.resize(t.header.size());
  for (long number = 2; std::getline(in, line); ++number) {
    const std::vector<std::string> cells = split(line);
    if (cells.size() != t.header.size())
      throw std::invalid_argument(path.string() + ":" + std::to_string(number) + ": " +
                                  std::to_string(cells.size()) + " values, the header has " +
                                  std::to_string(t.header.size()));
    for (std::size_t c = 0; c < cells.size(); ++c) t.cells[c].push_back(cells[c]);
    ++t.rows;
  }
  return t;
}

bool parse_number(const std::string& cell, double& v) {
  char* end = nullptr;
  v = std::strtod(cell.c_str(), &end);
  return !cell.empty() && end == cell.c_str() + cell.size();
}

// A column as numbers; false when a cell is not one (a column of names).
bool numbers(const std::vector<std::string>& cells, std::vector<double>& out) {
  out.resize(cells.size());
  for (std::size_t k = 0; k < cells.size(); ++k)
    if (!parse_number(cells[k], out[k])) return false;
  return true;
}

// The largest difference of two columns over the reference's largest magnitude.
double column_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double scale = 0, diff = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::isfinite(a[k])) scale = std::max(scale, std::abs(a[k]));
    const bool same = a[k] == b[k] || (std::isnan(a[k]) && std::isnan(b[k]));
    const double d = same ? 0.0 : std::abs(a[k] - b[k]);
    diff = std::isnan(d) || std::isinf(d) ? INFINITY : std::max(diff, d);
  }
  return diff / (scale > 0 ? scale : 1.0);
}

FileComparison compare_file(const fs::path& reference, const fs::path& other,
                            const std::string& name) {
  FileComparison f;
  f.name = name;
  if (!fs::exists(other)) {
    f.problem = "missing from " + other.parent_path().string();
    return f;
  }
  const Table a = read_table(reference), b = read_table(other);
  if (a.header != b.header) {
    f.problem = "the header differs";
    return f;
  }
  if (a.rows != b.rows) {
    f.problem = std::to_string(a.rows) + " rows, the other " + std::to_string(b.rows);
    return f;
  }
  for (std::size_t c = 0; c < a.header.size(); ++c) {
    std::vector<double> x, y;
    double d = 0;
    if (!numbers(a.cells[c], x)) {  // a column of names: equal or not
      d = a.cells[c] == b.cells[c] ? 0.0 : INFINITY;
    } else {
      for (std::size_t k = 0; k < b.cells[c].size(); ++k)
        if (double v = 0; !parse_number(b.cells[c][k], v))
          throw std::invalid_argument(other.string() + ":" + std::to_string(k + 2) + ": column " +
                                      a.header[c] + ": '" + b.cells[c][k] + "' is not a number");
      numbers(b.cells[c], y);
      d = column_difference(x, y);
    }
    if (f.worst_column.empty() || !(d <= f.worst)) {
      f.worst = d;
      f.worst_column = a.header[c];
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

RunComparison compare_runs(const fs::path& reference, const fs::path& other, double tolerance) {
  RunComparison r;
  r.tolerance = tolerance;
  if (!fs::is_directory(other)) throw std::invalid_argument(other.string() + ": not a folder");
  for (const std::string& run : run_names(reference)) {
    ++r.runs;
    for (const std::string& file : compared_files()) {
      const fs::path a = reference / run / file;
      if (!fs::exists(a)) continue;
      const std::string name = run.empty() ? file : run + "/" + file;
      r.files.push_back(compare_file(a, other / run / file, name));
    }
  }
  return r;
}

}  // namespace railcosim::cli
