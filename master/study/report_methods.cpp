#include "study/report_methods.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>

#include "run/run_output.hpp"

namespace railcosim::study {
namespace {

bool is_cosim(const StudyRun& r) {
  return (r.group == "case" || r.group == "sweep") && r.method != "monolithic";
}

}  // namespace

const StudyRun* cheapest_reaching(const std::vector<StudyRun>& runs, double level) {
  const StudyRun* best = nullptr;
  for (const StudyRun& r : runs) {
    if (!is_cosim(r) || r.record.status != "ok" || !r.record.rel_l2_error ||
        *r.record.rel_l2_error > level)
      continue;
    if (!best || r.record.wall_s < best->record.wall_s) best = &r;
  }
  return best;
}

std::string reference_words(const std::vector<StudyRun>& runs) {
  const bool cosim = std::any_of(runs.begin(), runs.end(), [](const StudyRun& r) {
    return is_cosim(r) && r.record.reference_kind == "co-simulation";
  });
  return cosim ? "the co-simulation reference" : "the converged monolithic run";
}

std::optional<double> restart_ratio(const std::vector<StudyRun>& runs, const std::string& restart) {
  std::optional<double> j, gs;
  for (const StudyRun& r : runs) {
    if (r.group != "restart" || r.record.restart != restart || !r.record.rel_l2_error) continue;
    if (r.record.case_name == "rs-xx-jacobi") j = *r.record.rel_l2_error;
    if (r.record.case_name == "rs-xx-gauss-seidel") gs = *r.record.rel_l2_error;
  }
  if (!j || !gs || !(*gs > 0)) return std::nullopt;
  return *j / *gs;
}

void write_method_sections(std::ostream& md, const std::vector<StudyRun>& runs,
                           const std::string& h) {
  // Per method: the largest H at which it is stable (ok, or inaccurate: a
  // bounded error over its bound), and the first H above it at which it is
  // not; and the largest H at which it is ok.
  std::map<std::string, std::map<double, std::string>> status;
  std::vector<std::string> order;
  for (const StudyRun& r : runs) {
    if (!is_cosim(r)) continue;
    if (!status.count(r.method)) order.push_back(r.method);
    status[r.method][r.record.macro_step] = r.record.status;
  }
  md << "\n"
     << h << " Largest stable macro step per method\n\n"
     << "Stable: ok or inaccurate (the error is bounded but over its bound); not stable: "
        "amplified (the spectral radius of the macro-step map at rest, implicit coupling's "
        "converged step included, or where no map is computed the matrix-free rate or the "
        "stability probe, finds a growing perturbation), diverged, or not converged.\n\n"
     << "| method | largest H stable (s) | first H not stable (s): status | largest H ok (s) "
        "|\n|---|---|---|---|\n";
  for (const std::string& m : order) {
    std::optional<double> stable, ok;
    std::string broke = "–";
    for (const auto& [H, s] : status[m]) {  // ascending H
      const bool holds = s == "ok" || s == "inaccurate";
      if (holds && broke == "–") stable = H;
      if (!holds && broke == "–" && stable) broke = run::sci(H) + ": " + s;
      if (s == "ok" && broke == "–") ok = H;
    }
    md << "| " << m << " | " << (stable ? run::sci(*stable) : "none") << " | " << broke << " | "
       << (ok ? run::sci(*ok) : "none") << " |\n";
  }

  const auto consistent = restart_ratio(runs, "consistent");
  const auto carry = restart_ratio(runs, "carry");
  if (consistent || carry) {
    md << "\n"
       << h << " Restart convention and the paper's \"almost 10\"\n\n"
       << "Jacobi over Gauss–Seidel error at the rail/sleepers cut with X-X, H = 1e-4 s, 10 "
          "fixed micro steps per macro step. The paper reports \"almost 10\"; an independent "
          "reference gives 9.3 when each subsystem keeps its acceleration across a communication "
          "point (carry) and 32 to 46 when it restarts from an acceleration consistent with the "
          "new inputs. Judged: a ratio in [5, 20] reproduces \"almost 10\".\n\n"
       << "| convention | ratio (ours) | paper | reproduces \"almost 10\" |\n|---|---|---|---|\n";
    for (const auto& [name, v] :
         {std::pair{"consistent (default)", consistent}, std::pair{"carry", carry}}) {
      md << "| " << name << " | " << (v ? run::sci(*v) : "–") << " | almost 10 | "
         << (v ? (*v >= 5 && *v <= 20 ? "yes" : "no") : "not run") << " |\n";
    }
  }
}

}  // namespace railcosim::study
