// The paper's conclusions checked against a study's runs (report.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "run/run_output.hpp"
#include "study/report.hpp"

namespace railcosim {
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

// The Gauss–Seidel gain at the rail/sleepers cut counts as the paper's
// "almost 10" within this factor of 10.
constexpr double kGainFactor = 2.0;

// Why the rail/sleepers X-T Gauss–Seidel case breaks two of the paper's
// general statements here (the paper gives no numbers for it).
constexpr const char* kRsXtWhy =
    ". The exception is rs-xt-gauss-seidel: at the rail/sleepers cut S1 can only compute the pad "
    "forces at t_n + H from the sleeper state it held over the step, so under either schedule S2 "
    "receives forces built on a sleeper state one macro step old, and the fresher rail state "
    "that Gauss–Seidel brings does not pay off";

}  // namespace

std::vector<Finding> check_findings(const std::vector<StudyRun>& runs) {
  const auto c = cases_of(runs);
  std::vector<Finding> f;
  const std::vector<Method> methods = all_methods();
  const bool have_all = std::all_of(methods.begin(), methods.end(), [&](const Method& m) {
    return c.count(m.label()) && c.at(m.label())->status != "failed";
  });
  if (!have_all) {
    f.push_back({"The paper's comparison of the eight cases", "not checked",
                 "the study did not run every case (or some failed)"});
    return f;
  }

  {  // 1. Jacobi X-T at the W/R cut: abnormal amplification, the biggest error.
    const RunRecord* a = c.at("wr-xt-jacobi");
    bool biggest = usable(a);
    double second = 0;
    // Against the paper's other cases only (a scene may add cuts and methods).
    for (const Method& m : methods) {
      const std::string k = m.label();
      const RunRecord* r = c.at(k);
      if (k == "wr-xt-jacobi" || k == "wr-xt-jacobi-resolved" || !usable(r) || !usable(a)) continue;
      second = std::max(second, *r->rel_l2_error);
      biggest = biggest && *a->rel_l2_error > *r->rel_l2_error;
    }
    const bool ok = a->status == "amplified" && biggest;
    std::ostringstream e;
    e << "status " << a->status << ", history error "
      << (a->history_error ? sci(*a->history_error) : "n/a") << ", rel. L2 error "
      << (usable(a) ? sci(*a->rel_l2_error) : "n/a") << " against at most " << sci(second)
      << " for the paper's other cases";
    f.push_back(
        {"Jacobi X-T at the wheel/rail cut is abnormally amplified; its error is the "
         "biggest of all cases",
         ok ? "reproduced" : "not reproduced", e.str()});
    f.back().paper = "abnormally amplified; the biggest error of the eight cases";
    f.back().judged =
        "status amplified (unstable: in the stability probe a perturbation of the static state "
        "grows more than 1000-fold) and a rel. L2 error above every other case's";
  }
  {  // 2. GS X-T at the W/R cut: a similar but weaker tendency.
    const RunRecord* gs = c.at("wr-xt-gauss-seidel");
    const RunRecord* gsxx = c.at("wr-xx-gauss-seidel");
    const RunRecord* j = c.at("wr-xt-jacobi");
    std::set<double> amplified_at;
    for (const auto& r : runs)
      if (r.method == "wr-xt-gauss-seidel" &&
          (r.record.status == "amplified" || r.record.status == "diverged"))
        amplified_at.insert(r.record.macro_step);
    const double hg = gs->history_error.value_or(NAN), hx = gsxx->history_error.value_or(NAN),
                 hj = j->history_error.value_or(NAN);
    const bool weaker = hg < hj && hg > hx;
    std::ostringstream e;
    e << "at the scene's H: history error " << sci(hg) << " (status " << gs->status
      << "), between Gauss–Seidel X-X (" << sci(hx) << ") and Jacobi X-T (" << sci(hj) << ")";
    if (!amplified_at.empty()) {
      e << "; amplified or diverged at H =";
      for (double H : amplified_at) e << " " << H;
      e << " s";
    }
    f.push_back(
        {"Gauss–Seidel X-T at the wheel/rail cut shows a similar but less amplified tendency",
         weaker && !amplified_at.empty() ? "reproduced"
         : weaker                        ? "partly reproduced"
                                         : "not reproduced",
         e.str()});
    f.back().paper = "a similar but less amplified tendency than Jacobi X-T";
    f.back().judged =
        "history error between Gauss–Seidel X-X's and Jacobi X-T's; reproduced when the case is "
        "also amplified or diverged at some macro step of the sweep";
  }
  {  // 3. GS instead of Jacobi divides the R/S X-X error by almost 10.
    const double ratio = err(c, "rs-xx-jacobi") / err(c, "rs-xx-gauss-seidel");
    // Within a factor kGainFactor of the paper's 10; a gain outside it is
    // reported as what it is (better, but not by almost 10).
    const bool near = ratio >= 10.0 / kGainFactor && ratio <= 10.0 * kGainFactor;
    std::string e = "ratio " + sci(ratio, 1) + " (" + err_of(c, "rs-xx-jacobi") + ", " +
                    err_of(c, "rs-xx-gauss-seidel") + "), restart convention " +
                    c.at("rs-xx-jacobi")->restart;
    if (!near && ratio > 1) {
      char times[32];
      std::snprintf(times, sizeof times, "%.1f", ratio / 10.0);
      e += std::string(": Gauss–Seidel is better by ") + times +
           " times the paper's factor, not by almost 10";
    }
    f.push_back(
        {"At the rail/sleepers cut with X-X, Gauss–Seidel divides the error of Jacobi by "
         "almost 10",
         near        ? "reproduced"
         : ratio > 1 ? "partly reproduced"
                     : "not reproduced",
         e});
    f.back().paper = "almost 10";
    f.back().judged =
        "reproduced for a ratio within a factor 2 of 10 (5 to 20), partly reproduced for any "
        "other ratio above 1; the scene's simulation.restart sets the convention (with 10 fixed "
        "micro steps per macro step, carry, the paper's, gives about 9.3 and consistent about "
        "32)";
  }
  {  // 4. GS generally more accurate than Jacobi.
    int better = 0;
    std::string e;
    for (const char* st : {"wr-xx", "wr-xt", "rs-xx", "rs-xt"}) {
      const double j = err(c, std::string(st) + "-jacobi"),
                   g = err(c, std::string(st) + "-gauss-seidel");
      better += g < j;
      e += std::string(e.empty() ? "" : "; ") + st + ": Jacobi " + sci(j) + ", Gauss–Seidel " +
           sci(g);
    }
    f.push_back({"The sequential Gauss–Seidel scheme is generally more accurate than Jacobi",
                 better == 4   ? "reproduced"
                 : better >= 3 ? "partly reproduced"
                               : "not reproduced",
                 std::to_string(better) + " of 4 cut/type pairs (" + e + ")"});
    f.back().paper = "generally more accurate";
    f.back().judged = "lower rel. L2 error in 4 of 4 cut/type pairs (3 of 4: partly)";
  }
  {  // 5 and 6. X-X better at W/R, reversed at R/S.
    for (const char* split : {"wr", "rs"}) {
      const bool wr = std::string(split) == "wr";
      int holds = 0;
      std::string e;
      for (const char* sch : {"jacobi", "gauss-seidel"}) {
        const double xx = err(c, std::string(split) + "-xx-" + sch),
                     xt = err(c, std::string(split) + "-xt-" + sch);
        holds += wr ? xx < xt : xt < xx;
        e += std::string(e.empty() ? "" : "; ") + sch + ": X-X " + sci(xx) + ", X-T " + sci(xt);
      }
      if (!wr && err(c, "rs-xt-gauss-seidel") >= err(c, "rs-xx-gauss-seidel")) e += kRsXtWhy;
      f.push_back({wr ? "At the wheel/rail cut, X-X is more accurate than X-T"
                      : "At the rail/sleepers cut the tendency is reversed: X-T is more accurate "
                        "than X-X",
                   holds == 2   ? "reproduced"
                   : holds == 1 ? "partly reproduced"
                                : "not reproduced",
                   std::to_string(holds) + " of 2 schemes (" + e + ")"});
      f.back().paper = wr ? "X-X more accurate than X-T at the wheel/rail cut"
                          : "X-T more accurate than X-X at the rail/sleepers cut";
      f.back().judged = "lower rel. L2 error under both schemes (one of two: partly)";
    }
  }
  {  // 7. W/R more accurate than R/S, except Jacobi X-T.
    int holds = 0, pairs = 0;
    std::string e;
    for (const char* ts : {"xx-jacobi", "xx-gauss-seidel", "xt-gauss-seidel"}) {
      const double wr = err(c, std::string("wr-") + ts), rs = err(c, std::string("rs-") + ts);
      holds += wr < rs;
      ++pairs;
      e += std::string(e.empty() ? "" : "; ") + ts + ": W/R " + sci(wr) + ", R/S " + sci(rs);
    }
    f.push_back({"The wheel/rail cut gives the more accurate deflection (except Jacobi X-T)",
                 holds == pairs ? "reproduced"
                 : holds > 0    ? "partly reproduced"
                                : "not reproduced",
                 std::to_string(holds) + " of " + std::to_string(pairs) + " (" + e + ")"});
    f.back().paper = "the wheel/rail cut more accurate, except Jacobi X-T";
    f.back().judged = "lower rel. L2 error at W/R in all three pairs (some: partly)";
  }
  {  // 8. R/S more stable: fewer non-ok cells in the sweep.
    std::map<std::string, int> bad, total;
    for (const auto& r : runs) {
      if (r.group == "tolerance" || r.method == "monolithic" ||
          r.method.find("resolved") != std::string::npos)
        continue;
      const std::string split = r.method.substr(0, 2);
      ++total[split];
      bad[split] += r.record.status == "amplified" || r.record.status == "diverged";
    }
    const bool holds = bad["rs"] < bad["wr"];
    f.push_back({"The rail/sleepers cut remains more stable",
                 holds                    ? "reproduced"
                 : bad["rs"] == bad["wr"] ? "partly reproduced"
                                          : "not reproduced",
                 "amplified or diverged runs over the macro-step sweep (lagged methods): W/R " +
                     std::to_string(bad["wr"]) + " of " + std::to_string(total["wr"]) + ", R/S " +
                     std::to_string(bad["rs"]) + " of " + std::to_string(total["rs"])});
    f.back().paper = "the rail/sleepers cut remains more stable";
    f.back().judged =
        "fewer amplified or diverged runs at R/S than at W/R over the sweep (equal: partly)";
  }
  {  // Beyond the paper: the resolved feedthrough.
    const RunRecord* r = c.at("wr-xt-jacobi-resolved");
    f.push_back(
        {"(This project) Resolved feedthrough removes the amplification of Jacobi X-T at "
         "the wheel/rail cut",
         r->status == "ok" && err(c, "wr-xt-jacobi-resolved") < 2 * err(c, "wr-xx-jacobi")
             ? "reproduced"
             : "not reproduced",
         "status " + r->status + ", " + err_of(c, "wr-xt-jacobi-resolved") + " against " +
             err_of(c, "wr-xx-jacobi")});
    f.back().paper = "– (not in the paper)";
    f.back().judged = "status ok and an error below twice Jacobi X-X's at the same cut";
  }
  return f;
}

}  // namespace railcosim
