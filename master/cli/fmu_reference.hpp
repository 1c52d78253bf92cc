// `master fmu check FILE.fmu --reference REF.csv`: an FMU's run of its
// default experiment held against a record of its outputs, such as the
// `<model>_ref.csv` files published beside FMI reference models. The CSV's
// header names the columns (quoted or not), the first the time; each row's
// values are compared with the FMU's at the communication point of the same
// time. Rows between communication points (an event's instant in a record
// made by another host) and after the stop time are counted, not compared;
// where two rows share a time (the values before and after an event), the
// FMU's value may match either.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "description.hpp"

namespace railcosim::cli {

// Bounds on a reference file, checked before anything is kept of it.
inline constexpr std::uintmax_t kMaxReferenceBytes = std::uintmax_t{256} << 20;
inline constexpr std::size_t kMaxReferenceRows = 1'000'000;
inline constexpr std::size_t kMaxReferenceColumns = 10'000;

struct ReferenceTable {
  std::string file;
  std::vector<std::string> names;  // the columns after the time
  std::vector<double> times;
  // rows[i][c]: the cell's numbers (several, space-separated, for an array);
  // empty where a cell is not numbers.
  std::vector<std::vector<std::vector<double>>> rows;
};

// Reads the file; throws fmu::FmuError naming the file, the line and what
// is wrong (no header, a first column that is not the time, a row of
// another width, a time that is not a number or goes back, a bound).
ReferenceTable read_reference_csv(const std::string& file);

struct ReferenceColumn {
  std::string name;
  std::string skipped;  // why it is not compared; "" when it is
  long compared = 0;    // communication points compared
  double worst = 0;     // the largest |FMU - reference| over them
  double worst_t = 0;   // where it is
  double scale = 0;     // max |reference| over the compared rows: the tolerance is rtol x scale
  bool pass = true;
  std::string mismatch;  // where the FMU's values and the record's differ in number
};

struct ReferenceComparison {
  std::string file;
  double rtol = 0;
  long rows = 0, on_grid = 0, between = 0, after_stop = 0;
  std::vector<ReferenceColumn> columns;
  // At least one column compared at one point, and every compared one within its tolerance.
  bool pass() const;
};

// What the run must record, and the comparison once it has.
class ReferenceRecorder {
 public:
  // The table's columns matched with the FMU's variables by name, its rows
  // with the communication points start + n step, n = 0 .. steps.
  ReferenceRecorder(ReferenceTable table, const fmu::ModelDescription& d, double start, double step,
                    long steps);
  // The variables to read at a point the table needs (in the table's column order).
  const std::vector<const fmu::Variable*>& variables() const { return vars_; }
  bool wants(long n) const { return wanted_.count(n) != 0; }
  // The values of variables() at point n, each variable's in its order.
  void record(long n, std::vector<std::vector<double>> values) { recorded_[n] = std::move(values); }
  ReferenceComparison compare(double rtol) const;

 private:
  ReferenceTable table_;
  double start_ = 0, step_ = 0;
  std::vector<long> point_;                 // per row: its point n, -1 between, -2 after stop
  std::vector<const fmu::Variable*> vars_;  // compared columns' variables
  std::vector<int> column_var_;             // per column: index into vars_, -1 skipped
  std::vector<std::string> skipped_;        // per column: why not compared
  std::map<long, bool> wanted_;
  std::map<long, std::vector<std::vector<double>>> recorded_;
};

}  // namespace railcosim::cli
