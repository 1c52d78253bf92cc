// The paper's conclusions checked against a study's runs (report.hpp): each
// row of the findings table (report_findings_table.cpp) measured by its
// measure function, here.
#include "study/report_findings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "run/run_output.hpp"

namespace railcosim::study {

using run::RunRecord;
using run::sci;

namespace {

// The runs at the scene's macro step, by method label.
std::map<std::string, const RunRecord*> cases_of(const std::vector<StudyRun>& runs) {
  std::map<std::string, const RunRecord*> m;
  for (const auto& r : runs)
    if (r.group == "case") m[r.method] = &r.record;
  return m;
}

bool usable(const RunRecord* r) {
  return r && r->rel_l2_error.has_value();
}

std::string err_of(const std::map<std::string, const RunRecord*>& c, const std::string& k) {
  const auto it = c.find(k);
  if (it == c.end() || !usable(it->second)) return k + ": n/a";
  return k + ": " + sci(*it->second->rel_l2_error);
}

double err(const std::map<std::string, const RunRecord*>& c, const std::string& k) {
  const auto it = c.find(k);
  return it != c.end() && usable(it->second) ? *it->second->rel_l2_error : NAN;
}

// "reproduced" when all of `n` hold, "partly reproduced" when at least
// `partly` do, else "not reproduced".
std::string count_verdict(int holds, int n, int partly) {
  return holds == n ? "reproduced" : holds >= partly ? "partly reproduced" : "not reproduced";
}

}  // namespace

// The row's run is amplified and its error the biggest of the paper's cases
// (the other run of the row aside).
Measured amplified_and_biggest(const FindingRow& row, const FindingRuns& in) {
  const RunRecord* a = in.cases.at(row.runs[0]);
  bool biggest = usable(a);
  double second = 0;
  // Against the paper's other cases only (a scene may add cuts and methods).
  for (const Method& m : in.methods) {
    const std::string k = m.label();
    const RunRecord* r = in.cases.at(k);
    if (k == row.runs[0] || k == row.runs[1] || !usable(r) || !usable(a)) continue;
    second = std::max(second, *r->rel_l2_error);
    biggest = biggest && *a->rel_l2_error > *r->rel_l2_error;
  }
  const bool ok = a->status == "amplified" && biggest;
  std::ostringstream e;
  e << "status " << a->status << ", history error "
    << (a->history_error ? sci(*a->history_error) : "n/a") << ", rel. L2 error "
    << (usable(a) ? sci(*a->rel_l2_error) : "n/a") << " against at most " << sci(second)
    << " for the paper's other cases";
  return {ok ? "reproduced" : "not reproduced", e.str()};
}

// The row's run has a history error between those of its other two runs;
// fully reproduced when it is also amplified or diverged somewhere in the sweep.
Measured history_error_between(const FindingRow& row, const FindingRuns& in) {
  const RunRecord* run = in.cases.at(row.runs[0]);
  const RunRecord* below = in.cases.at(row.runs[1]);
  const RunRecord* above = in.cases.at(row.runs[2]);
  std::set<double> amplified_at;
  for (const auto& r : in.runs)
    if (r.method == row.runs[0] &&
        (r.record.status == "amplified" || r.record.status == "diverged"))
      amplified_at.insert(r.record.macro_step);
  const double h = run->history_error.value_or(NAN), lo = below->history_error.value_or(NAN),
               hi = above->history_error.value_or(NAN);
  const bool weaker = h < hi && h > lo;
  std::ostringstream e;
  e << "at the scene's H: history error " << sci(h) << " (status " << run->status << "), between "
    << row.sides[0] << " (" << sci(lo) << ") and " << row.sides[1] << " (" << sci(hi) << ")";
  if (!amplified_at.empty()) {
    e << "; amplified or diverged at H =";
    for (double H : amplified_at) e << " " << H;
    e << " s";
  }
  return {weaker && !amplified_at.empty() ? "reproduced"
          : weaker                        ? "partly reproduced"
                                          : "not reproduced",
          e.str()};
}

// The first run's error over the second's, within a factor `tolerance` of
// the paper's number; a gain outside it is reported as what it is.
Measured error_ratio(const FindingRow& row, const FindingRuns& in) {
  const RunPair& p = row.pairs[0];
  const double ratio = err(in.cases, p.first) / err(in.cases, p.second);
  const bool near =
      ratio >= row.paper_value / row.tolerance && ratio <= row.paper_value * row.tolerance;
  std::string e = "ratio " + sci(ratio, 1) + " (" + err_of(in.cases, p.first) + ", " +
                  err_of(in.cases, p.second) + "), restart convention " +
                  in.cases.at(p.first)->restart;
  if (!near && ratio > 1) {
    char times[32];
    std::snprintf(times, sizeof times, "%.1f", ratio / row.paper_value);
    e += ": " + row.sides[1] + " is better by " + times + " times the paper's factor, not by " +
         row.paper;
  }
  return {near ? "reproduced" : ratio > 1 ? "partly reproduced" : "not reproduced", e};
}

// In how many of the row's pairs the run the paper finds more accurate has
// the lower rel. L2 error.
Measured lower_error_in_pairs(const FindingRow& row, const FindingRuns& in) {
  int holds = 0;
  const int n = static_cast<int>(row.pairs.size());
  std::string e;
  bool noted = false;
  for (const RunPair& p : row.pairs) {
    const double first = err(in.cases, p.first), second = err(in.cases, p.second);
    const double lower = row.lower == 0 ? first : second, other = row.lower == 0 ? second : first;
    holds += lower < other;
    e += (e.empty() ? "" : "; ") + p.name + ": " + row.sides[0] + " " + sci(first) + ", " +
         row.sides[1] + " " + sci(second);
    noted = noted || (p.name == row.note_pair && lower >= other);
  }
  if (noted) e += row.note;  // inside the parentheses, after the pairs
  return {count_verdict(holds, n, n - static_cast<int>(row.tolerance)),
          std::to_string(holds) + " of " + std::to_string(n) + row.counted + " (" + e + ")"};
}

// Fewer amplified or diverged runs at the second cut than at the first over
// the macro-step sweep (lagged methods).
Measured fewer_unstable_runs(const FindingRow& row, const FindingRuns& in) {
  std::map<std::string, int> bad, total;
  for (const auto& r : in.runs) {
    if (r.group == "tolerance" || r.method == "monolithic" ||
        r.method.find("resolved") != std::string::npos)
      continue;
    const std::string split = r.method.substr(0, 2);
    ++total[split];
    bad[split] += r.record.status == "amplified" || r.record.status == "diverged";
  }
  const std::string& a = row.runs[0];
  const std::string& b = row.runs[1];
  return {bad[b] < bad[a]    ? "reproduced"
          : bad[b] == bad[a] ? "partly reproduced"
                             : "not reproduced",
          "amplified or diverged runs over the macro-step sweep (lagged methods): " + row.sides[0] +
              " " + std::to_string(bad[a]) + " of " + std::to_string(total[a]) + ", " +
              row.sides[1] + " " + std::to_string(bad[b]) + " of " + std::to_string(total[b])};
}

// The first run is ok and its error below `tolerance` times the second's.
Measured stable_and_below_factor(const FindingRow& row, const FindingRuns& in) {
  const RunRecord* r = in.cases.at(row.runs[0]);
  const RunRecord* from = in.cases.count(row.runs[2]) ? in.cases.at(row.runs[2]) : nullptr;
  const bool slow = r->spectral_rate && from && from->spectral_rate &&
                    *r->spectral_rate <= 0.1 * *from->spectral_rate;
  const bool ok = (r->status == "ok" || slow) &&
                  err(in.cases, row.runs[0]) < row.tolerance * err(in.cases, row.runs[1]);
  std::string growth;
  if (r->spectral_rate && from && from->spectral_rate)
    growth = " (growth rate " + run::sci(*r->spectral_rate) + " 1/s against " +
             run::sci(*from->spectral_rate) + " 1/s of " + row.runs[2] + ")";
  return {ok ? "reproduced" : "not reproduced", "status " + r->status + growth + ", " +
                                                    err_of(in.cases, row.runs[0]) + " against " +
                                                    err_of(in.cases, row.runs[1])};
}

std::vector<Finding> check_findings(const std::vector<StudyRun>& runs) {
  const FindingRuns in{runs, cases_of(runs), all_methods()};
  const bool have_all = std::all_of(in.methods.begin(), in.methods.end(), [&](const Method& m) {
    return in.cases.count(m.label()) && in.cases.at(m.label())->status != "failed";
  });
  if (!have_all)
    return {{"The paper's comparison of the eight cases", "not checked",
             "the study did not run every case (or some failed)"}};
  std::vector<Finding> f;
  for (const FindingRow& row : kFindingTable) {
    Measured m = row.measure(row, in);
    f.emplace_back(row.claim, std::move(m.verdict), std::move(m.evidence));
    f.back().paper = row.paper;
    f.back().judged = row.judged;
  }
  return f;
}

}  // namespace railcosim::study
