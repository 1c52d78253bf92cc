#include "report.hpp"
#include "report_methods.hpp"
#include "report_spectra.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "log.hpp"
#include "run_output.hpp"
#include "scene.hpp"
#include "study_plan.hpp"

namespace railcosim {
namespace {

std::string sci(double v, int digits = 2) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*e", digits, v);
  return buf;
}

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

// Runs a shell command; true on exit status 0.
bool shell(const std::string& cmd) {
  return std::system(cmd.c_str()) == 0;
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The interpreter that has matplotlib: Debian's first, then whatever is on PATH.
std::string find_python() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (shell(std::string(py) + " -c 'import matplotlib' >/dev/null 2>&1")) return py;
  return "";
}

std::string figure_script(const std::string& given) {
  if (!given.empty()) return given;
  if (const char* env = std::getenv("RAILCOSIM_FIGURES")) return env;
  return std::string(RAILCOSIM_SOURCE_DIR) + "/scripts/figures.py";
}

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
        "status amplified (history error over cosim.amplification_threshold, or deflection error "
        "over 25 %) and a rel. L2 error above every other case's";
  }
  {  // 2. GS X-T at the W/R cut: a similar but weaker tendency.
    const RunRecord* gs = c.at("wr-xt-gauss-seidel");
    const RunRecord* gsxx = c.at("wr-xx-gauss-seidel");
    const RunRecord* j = c.at("wr-xt-jacobi");
    std::set<double> amplified_at;
    for (const auto& r : runs)
      if (r.method == "wr-xt-gauss-seidel" && r.record.status != "ok" &&
          r.record.status != "failed")
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

namespace {

// Draws FOLDER/figures/*.png from FOLDER/summary.csv. Returns "" when drawn,
// otherwise the sentence saying why not.
std::string draw_figures(const std::filesystem::path& folder, const std::string& script) {
  auto log = logger("master");
  std::string note;
  const std::string py = find_python();
  if (py.empty()) {
    note =
        "Figures were not drawn: no Python with matplotlib was found (install Debian's "
        "python3-matplotlib). Every CSV is written; run `/usr/bin/python3 scripts/figures.py ";
    note += folder.string();
    note += "` once it is installed.";
  } else if (!shell(py + " " + quote(script) + " " + quote(folder.string()))) {
    note = "Figures were not drawn: ";
    note += script;
    note += " failed on ";
    note += folder.string();
    note += " (see the messages above).";
  }
  if (!note.empty()) log->warn("{}", note);
  return note;
}

std::string scene_line(const Scene& s) {
  std::ostringstream md;
  md << s.sleeper_count << " sleepers (" << s.track_length() << " m of rail), " << s.speed * 3.6
     << " km/h, t_end = " << s.end_time << " s, macro step H = " << s.macro_step
     << " s, micro-step tolerance " << s.tolerance << " m";
  return md.str();
}

// The sections of one scene (the study's, or one variant of a sweep), headed
// at level H; FIGURES is the figures' folder relative to REPORT.md.
void scene_sections(std::ostringstream& md, const std::string& h, const Scene& scene,
                    const std::vector<StudyRun>& runs, const std::string& transport,
                    const std::string& figures, const std::string& figures_note,
                    const std::filesystem::path& dir) {
  md << h
     << " The paper's conclusions\n\n| conclusion | paper | ours | judged with | verdict "
        "|\n|---|---|---|---|---|\n";
  std::vector<StudyRun> there;  // a missing case leaves the comparison "not checked"
  for (const StudyRun& r : runs)
    if (r.record.status != "missing") there.push_back(r);
  for (const Finding& f : check_findings(there))
    md << "| " << f.claim << " | " << f.paper << " | " << f.evidence << " | " << f.judged << " | **"
       << f.verdict << "** |\n";

  md << "\n"
     << h << " Runs at H = " << scene.macro_step << " s\n\n"
     << "| method | status | rel. L2 error | max abs error (m) | history error | wall (s) | micro "
        "steps |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const auto& r : runs) {
    if (r.group != "case") continue;
    const RunRecord& x = r.record;
    std::string micro;
    for (const auto& [k, v] : x.micro_steps)
      micro += (micro.empty() ? "" : ", ") + k + " " + std::to_string(v);
    md << "| " << r.method << " | " << x.status << " | "
       << (x.rel_l2_error ? sci(*x.rel_l2_error) : "–") << " | "
       << (x.max_abs_error_m ? sci(*x.max_abs_error_m) : "–") << " | "
       << (x.history_error ? sci(*x.history_error) : "–") << " | " << sci(x.wall_s) << " | "
       << micro << " |\n";
  }

  md << "\n" << h << " Figures\n\n";
  if (figures_note.empty()) {
    md << "Rail deflection at t_end, every case over the monolithic one (the paper's Figure 5):\n\n"
       << "![deflection](" << figures << "/deflection.png)\n\n"
       << "Deflection error against the monolithic run, per cut and schedule (the paper's Figure "
          "6):\n\n"
       << "![errors](" << figures << "/errors.png)\n\n"
       << "Speed against accuracy: each point a macro step of the sweep; the monolithic run across "
          "tolerances is the reference curve:\n\n"
       << "![speed and accuracy](" << figures << "/speed_accuracy.png)\n\n"
       << "Stability map: macro step against method:\n\n![stability](" << figures
       << "/stability_map.png)\n\n"
       << "Contact force: the monolithic run, the best and the worst co-simulation:\n\n"
       << "![contact force](" << figures << "/contact_force.png)\n";
  } else {
    md << figures_note << "\n";
  }

  // The stability map as a table too (it is read without the figure).
  std::set<double> hs;
  std::map<std::string, std::map<double, std::string>> map;
  std::vector<std::string> order;
  for (const auto& r : runs) {
    if (r.group == "tolerance" || r.group == "converged" || r.method == "monolithic") continue;
    hs.insert(r.record.macro_step);
    if (!map.count(r.method)) order.push_back(r.method);
    map[r.method][r.record.macro_step] = r.record.status;
  }
  md << "\n" << h << " Stability map\n\n| method |";
  for (double H : hs) md << " H = " << H << " s |";
  md << "\n|---|";
  for (std::size_t i = 0; i < hs.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& m : order) {
    md << "| " << m << " |";
    for (double H : hs) md << " " << (map[m].count(H) ? map[m][H] : "–") << " |";
    md << "\n";
  }

  write_method_sections(md, runs, transport, h);
  const bool spectra_figure =
      figures_note.empty() && std::filesystem::exists(dir / "figures" / "spectra.png");
  write_spectra_section(md, dir, spectra_figure ? figures + "/spectra.png" : "", h);
}

// Runs that are missing or failed, and a stage still to run.
void incomplete_section(std::ostringstream& md, const StudyReportInfo& info,
                        const std::vector<StudyRun>& runs) {
  int missing = 0, failed = 0;
  for (const auto& r : runs) {
    missing += r.record.status == "missing";
    failed += r.record.status == "failed";
  }
  if (missing + failed > 0) {
    md << "## Incomplete study\n\n"
       << missing << " of " << runs.size() << " runs are missing and " << failed
       << " failed; the tables below are drawn from the runs there are.\n\n"
       << "| folder | status | why |\n|---|---|---|\n";
    for (const auto& r : runs)
      if (r.record.status == "missing" || r.record.status == "failed")
        md << "| " << r.folder << " | " << r.record.status << " | " << r.record.message << " |\n";
    md << "\n";
  }
  const std::string other = info.transport == "tcp" ? "inproc" : "tcp";
  if (info.stage2_pending)
    md << "Stage 2 of the plan, the cheapest methods rerun over `" << other
       << "`, is written to `plan-2.txt` and not run yet: run its commands like those of "
          "`plan.txt`, then collect again.\n\n";
  else if (!info.stage1_complete)
    md << "Stage 2 of the plan (the cheapest methods rerun over `" << other
       << "`) is planned once every run of stage 1 is there.\n\n";
}

}  // namespace

void write_report(const StudyReportInfo& info, const std::vector<StudyRun>& runs) {
  const std::string script = figure_script(info.figure_script);
  const bool swept = !info.sweeps.empty();
  const Scene base = load_scene((info.dir / "scene.toml").string());

  std::ostringstream md;
  md << "# Study of the `" << base.name << "` scene\n\n";
  md << "Scene file `" << info.source_scene << "` (copied to `scene.toml`): " << scene_line(base)
     << ". Co-simulation runs over `" << info.transport << "`. Errors are relative L2 norms of the "
     << "rail deflection at t_end against the monolithic run with the same H and tolerance; the "
     << "speed/accuracy chart measures every run against a converged monolithic run (tolerance "
     << info.converged_tolerance << " m) instead.\n\n";
  if (swept) {
    md << "Swept scene values:";
    for (const SweepAxis& a : info.sweeps) {
      md << " `" << a.key << "` =";
      for (std::size_t i = 0; i < a.values.size(); ++i) md << (i ? ", " : " ") << a.values[i];
      md << ";";
    }
    md << " each combination is a scene variant with its own folder, `scene.toml`, "
          "`summary.csv`, figures and section below.\n\n";
  }
  incomplete_section(md, info, runs);

  for (const auto& [label, vdir] : info.variants) {
    std::vector<StudyRun> vr;  // folders relative to the variant's, as figures.py reads them
    for (const StudyRun& r : runs)
      if (r.variant == label) {
        vr.push_back(r);
        if (!vdir.empty()) vr.back().folder = r.folder.substr(vdir.size() + 1);
      }
    if (swept) {
      write_summary_csv(info.dir / vdir / "summary.csv", vr);
      const std::string note = draw_figures(info.dir / vdir, script);
      const Scene scene = load_scene((info.dir / vdir / "scene.toml").string());
      md << "## " << label << "\n\nScene variant `" << vdir << "/scene.toml`: " << scene_line(scene)
         << ".\n\n";
      scene_sections(md, "###", scene, vr, info.transport, vdir + "/figures", note,
                     info.dir / vdir);
      md << "\n";
    } else {
      const std::string note = draw_figures(info.dir, script);
      scene_sections(md, "##", base, vr, info.transport, "figures", note, info.dir);
    }
  }

  md << "\n## Every run\n\n| folder |" << (swept ? " variant |" : "")
     << " case | feedthrough | H (s) | tolerance (m) | wall (s) | micro steps | rel. L2 error | "
        "error vs converged | status |\n|---|"
     << (swept ? "---|" : "") << "---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : runs) {
    const RunRecord& x = r.record;
    long micro = 0;
    for (const auto& [k, v] : x.micro_steps) micro += v;
    const bool has = x.status == "ok" || x.status == "amplified";
    md << "| " << r.folder << " | " << (swept ? r.variant + " | " : "") << x.case_name << " | "
       << x.feedthrough.value_or("–") << " | " << x.macro_step << " | " << r.tolerance << " | "
       << sci(x.wall_s) << " | " << micro << " | " << (x.rel_l2_error ? sci(*x.rel_l2_error) : "–")
       << " | " << (has ? sci(r.rel_l2_error_converged) : "–") << " | " << x.status
       << (x.status == "failed" || x.status == "missing" ? " (" + x.message + ")" : "") << " |\n";
  }
  write_file_atomically(info.dir / "REPORT.md", md.str());  // checked: never a 0-byte report
}

}  // namespace railcosim
