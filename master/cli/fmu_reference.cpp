#include "cli/fmu_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "fmu.hpp"
#include "fmu_error.hpp"

namespace railcosim::cli {
namespace {

using fmu::FmuError;

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    const auto first = cell.find_first_not_of(" \t\r");
    const auto last = cell.find_last_not_of(" \t\r");
    cell = first == std::string::npos ? "" : cell.substr(first, last - first + 1);
    if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"')
      cell = cell.substr(1, cell.size() - 2);
    out.push_back(cell);
  }
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// A cell as a number: a decimal number, or true / false (1 / 0); NaN otherwise.
double number(const std::string& s) {
  if (s == "true") return 1;
  if (s == "false") return 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v))
    return std::numeric_limits<double>::quiet_NaN();
  return v;
}

// A cell's numbers: one, or an array's separated by spaces; empty when one is not a number.
std::vector<double> cell_values(const std::string& s) {
  std::vector<double> out;
  std::istringstream in(s);
  for (std::string word; in >> word;) {
    const double v = number(word);
    if (std::isnan(v)) return {};
    out.push_back(v);
  }
  return out;
}

}  // namespace

ReferenceTable read_reference_csv(const std::string& file) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec || !std::filesystem::is_regular_file(file))
    throw FmuError(file + ": cannot read the reference (not a regular file)");
  if (bytes > kMaxReferenceBytes)
    throw FmuError(file + ": the reference holds " + std::to_string(bytes) + " bytes, over " +
                   std::to_string(kMaxReferenceBytes));
  std::ifstream in(file);
  std::string line;
  ReferenceTable t;
  t.file = file;
  long n = 0;
  auto bad = [&](const std::string& what) {
    return FmuError(file + ":" + std::to_string(n) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> c = cells(line);
    if (t.names.empty() && t.times.empty()) {
      if (c.empty() || c[0] != "time") throw bad("the header's first column is not \"time\"");
      if (c.size() < 2 || c.size() - 1 > kMaxReferenceColumns)
        throw bad("the header names " + std::to_string(c.size() - 1) +
                  " columns beside the time (1 to " + std::to_string(kMaxReferenceColumns) + ")");
      t.names.assign(c.begin() + 1, c.end());
      continue;
    }
    if (c.size() != t.names.size() + 1)
      throw bad("a row of " + std::to_string(c.size()) + " cells under a header of " +
                std::to_string(t.names.size() + 1));
    if (t.times.size() == kMaxReferenceRows)
      throw bad("more than " + std::to_string(kMaxReferenceRows) + " rows");
    const double time = number(c[0]);
    if (std::isnan(time)) throw bad("the time '" + c[0] + "' is not a number");
    if (!t.times.empty() && time < t.times.back()) throw bad("the time goes back");
    t.times.push_back(time);
    std::vector<std::vector<double>> row;
    for (std::size_t i = 1; i < c.size(); ++i) row.push_back(cell_values(c[i]));
    t.rows.push_back(std::move(row));
  }
  if (t.names.empty()) throw FmuError(file + ": no header (\"time\",NAME,...)");
  if (t.times.empty()) throw FmuError(file + ": no rows under the header");
  return t;
}

bool ReferenceComparison::pass() const {
  bool any = false;
  for (const ReferenceColumn& c : columns) {
    if (!c.skipped.empty()) continue;
    if (!c.pass) return false;
    any = any || c.compared > 0;
  }
  return any;
}

ReferenceRecorder::ReferenceRecorder(ReferenceTable table, const fmu::ModelDescription& d,
                                     double start, double step, long steps)
    : table_(std::move(table)), start_(start), step_(step) {
  for (std::size_t c = 0; c < table_.names.size(); ++c) {
    const fmu::Variable* v = d.find(table_.names[c]);
    std::string why;
    if (v == nullptr)
      why = "the FMU has no variable of that name";
    else if (!fmu::Fmu::readable(d.version, v->type))
      why = "of type " + v->type + ", which the host cannot read";
    else
      for (const auto& row : table_.rows)
        if (row[c].empty()) why = "a cell that is not a number";
    skipped_.push_back(why);
    column_var_.push_back(why.empty() ? static_cast<int>(vars_.size()) : -1);
    if (why.empty()) vars_.push_back(v);
  }
  const double stop = start + static_cast<double>(steps) * step;
  for (double t : table_.times) {
    const double k = std::round((t - start) / step);
    long p = -1;
    if (t > stop + 1e-6 * step)
      p = -2;
    else if (k >= 0 && std::abs(start + k * step - t) <= 1e-6 * step)
      p = static_cast<long>(k);
    point_.push_back(p);
    if (p >= 0) wanted_[p] = true;
  }
}

ReferenceComparison ReferenceRecorder::compare(double rtol) const {
  ReferenceComparison r;
  r.file = table_.file;
  r.rtol = rtol;
  r.rows = static_cast<long>(table_.times.size());
  for (long p : point_) {
    r.on_grid += p >= 0;
    r.between += p == -1;
    r.after_stop += p == -2;
  }
  for (std::size_t c = 0; c < table_.names.size(); ++c) {
    ReferenceColumn col;
    col.name = table_.names[c];
    col.skipped = skipped_[c];
    if (col.skipped.empty()) {
      for (std::size_t i = 0; i < point_.size(); ++i)
        if (point_[i] >= 0)
          for (double x : table_.rows[i][c]) col.scale = std::max(col.scale, std::abs(x));
      const auto k = static_cast<std::size_t>(column_var_[c]);
      // Rows of one point (an event's before and after): the nearer counts.
      for (std::size_t i = 0; i < point_.size();) {
        std::size_t j = i + 1;
        while (j < point_.size() && point_[j] == point_[i]) ++j;
        const auto it = recorded_.find(point_[i]);
        if (point_[i] >= 0 && it != recorded_.end()) {
          double d = std::numeric_limits<double>::infinity();
          const std::vector<double>& ours = it->second[k];
          for (std::size_t m = i; m < j; ++m) {
            const std::vector<double>& ref = table_.rows[m][c];
            if (ref.size() != ours.size()) {
              col.mismatch = "the FMU gives " + std::to_string(ours.size()) +
                             " values where the record has " + std::to_string(ref.size());
              continue;
            }
            double e = 0;
            for (std::size_t q = 0; q < ref.size(); ++q)
              e = std::max(e, std::abs(ours[q] - ref[q]));
            d = std::min(d, e);
          }
          ++col.compared;
          if (d > col.worst || col.compared == 1) {
            col.worst = d;
            col.worst_t = start_ + static_cast<double>(point_[i]) * step_;
          }
        }
        i = j;
      }
      col.pass = col.worst <= rtol * col.scale && std::isfinite(col.worst);
    }
    r.columns.push_back(std::move(col));
  }
  return r;
}

}  // namespace railcosim::cli
