#include "study/report.hpp"
#include "study/report_front.hpp"
#include "study/report_methods.hpp"
#include "study/report_slopes.hpp"
#include "study/report_spectra.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "log.hpp"
#include "remote/peer_text.hpp"
#include "remote/transport.hpp"
#include "run/run_output.hpp"
#include "scene.hpp"
#include "study/study_plan.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/stability.hpp"

namespace railcosim::study {
namespace {

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

// The stability map as a table too (it is read without the figure): each
// run's verdict, and the spectral radius rho with its rate per second where
// one was measured: the map's, or, where that could not be built, the one
// measured through the participants ("matrix-free"). A run whose stability
// was not judged says so, whatever its errors.
std::string map_cell(const run::RunRecord& r) {
  const bool settled = r.status == "amplified" || r.status == "diverged" || r.status == "failed" ||
                       r.status == "not_converged";
  std::string cell = !settled && r.stability == verdict::kNotJudged ? "not judged" : r.status;
  const std::optional<double> rho = rho_of(r), rate = rho_rate_of(r);
  if (rho) {
    std::ostringstream s;
    s << std::setprecision(3) << ", ρ " << verdict::rho_words(*rho);
    if (rate) s << " (" << *rate << " /s)";
    if (rho_basis_of(r) == "matrix-free") s << " matrix-free";
    cell += s.str();
  }
  return cell;
}

void write_stability_map(std::ostringstream& md, const std::vector<StudyRun>& runs,
                         const std::string& h) {
  std::set<double> hs;
  std::map<std::string, std::map<double, std::string>> map;
  std::vector<std::string> order;
  for (const auto& r : runs) {
    // The restart check's runs (fixed micro steps) are not the method's.
    if (r.group == "tolerance" || r.group == "converged" || r.group == "restart" ||
        r.method == "monolithic")
      continue;
    hs.insert(r.record.macro_step);
    if (!map.count(r.method)) order.push_back(r.method);
    map[r.method][r.record.macro_step] = map_cell(r.record);
  }
  md << "\n"
     << h << " Stability map\n\n"
     << "Each run's status (`not judged` where its stability was not: the reason is in its "
        "summary.json) and, where it was measured, the spectral radius ρ of its macro-step "
        "map at rest with its growth rate per second (a perturbation grows by ρ per macro step, "
        "or per slow window of a multirate run; unstable when it e-folds within 20 times the "
        "run's duration): from the map itself, or, marked matrix-free, "
        "measured through the participants' save and restore where the map cannot be built "
        "(implicit coupling, a participant on a node given by address, a soil of its own).\n\n"
        "| method |";
  for (double H : hs) md << " H = " << H << " s |";
  md << "\n|---|";
  for (std::size_t i = 0; i < hs.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& m : order) {
    md << "| " << m << " |";
    for (double H : hs) md << " " << (map[m].count(H) ? map[m][H] : "–") << " |";
    md << "\n";
  }
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
    const run::RunRecord& x = r.record;
    std::string micro;
    for (const auto& [k, v] : x.micro_steps)
      micro += (micro.empty() ? "" : ", ") + k + " " + std::to_string(v);
    md << "| " << r.method << " | " << x.status << " | "
       << (x.rel_l2_error ? run::sci(*x.rel_l2_error) : "–") << " | "
       << (x.max_abs_error_m ? run::sci(*x.max_abs_error_m) : "–") << " | "
       << (x.history_error ? run::sci(*x.history_error) : "–") << " | " << run::sci(x.wall_s)
       << " | " << micro << " |\n";
  }

  md << "\n" << h << " Figures\n\n";
  // Without a monolithic run (a participant given by address, a soil of its
  // own) the figures draw each run over its co-simulation reference, where
  // the study wrote one; else they are left out.
  const bool monolithic = std::any_of(runs.begin(), runs.end(), [](const StudyRun& r) {
    return r.group == "case" && r.method == "monolithic";
  });
  const bool references = std::any_of(runs.begin(), runs.end(), [](const StudyRun& r) {
    return r.group == "case" && !r.record.reference_folder.empty();
  });
  const std::string over = monolithic ? "the monolithic run" : "its co-simulation reference";
  if (figures_note.empty()) {
    if (monolithic || references)
      md << "Rail deflection at t_end, every case over " << over
         << ", one panel per cut that ran (the paper's Figure 5):\n\n![deflection](" << figures
         << "/deflection.png)\n\n"
         << "Deflection error against " << over
         << ", per cut and schedule (the paper's Figure 6):\n\n![errors](" << figures
         << "/errors.png)\n\n";
    md << "Speed against accuracy, one panel per cut: each point a macro step of the sweep, "
       << (monolithic ? "the monolithic run across tolerances the reference in every panel"
                      : "against the co-simulation reference")
       << "; the runs of the report's answer (the cheapest to reach each accuracy) drawn bold "
          "and labelled:\n\n"
       << "![speed and accuracy](" << figures << "/speed_accuracy.png)\n\n"
       << "Stability map: macro step against method:\n\n![stability](" << figures
       << "/stability_map.png)\n";
    if (monolithic || references)
      md << "\nContact force: "
         << (monolithic ? "the monolithic run"
                        : "the co-simulation "
                          "reference of the best run")
         << ", the best and the worst co-simulation:\n\n"
         << "![contact force](" << figures << "/contact_force.png)\n";
  } else {
    md << figures_note << "\n";
  }

  write_stability_map(md, runs, h);
  write_front_table(md, study_front(runs, transport), runs, transport, h);
  write_method_sections(md, runs, h);
  write_slopes_section(md, error_slopes(runs), h, reference_words(runs));
  const bool spectra_figure =
      figures_note.empty() && std::filesystem::exists(dir / "figures" / "spectra.png");
  write_spectra_section(md, dir, spectra_figure ? figures + "/spectra.png" : "", h);
}

// Runs that are missing or failed, and a stage still to run.
void incomplete_section(std::ostringstream& md, const StudyReportInfo& info,
                        const std::vector<StudyRun>& runs) {
  int missing = 0, failed = 0, not_run = 0;
  for (const auto& r : runs) {
    missing += r.record.status == "missing";
    failed += r.record.status == "failed";
    not_run += r.record.status == "not_run";
  }
  if (missing + failed + not_run > 0) {
    md << "## Incomplete study\n\n"
       << missing << " of " << runs.size() << " runs are missing, " << failed << " failed and "
       << not_run << " not run (budget); the tables below are drawn from the runs there are.\n\n"
       << "| folder | status | why |\n|---|---|---|\n";
    for (const auto& r : runs)
      if (r.record.status == "missing" || r.record.status == "failed" ||
          r.record.status == "not_run")
        md << "| " << r.folder << " | " << remote::markdown_text(r.record.status) << " | "
           << remote::markdown_text(r.record.message) << " |\n";
    md << "\n";
  }
  const std::string other = remote::other_transport(info.transport);
  if (info.stage2_pending)
    md << "Stage 2 of the plan, the cheapest methods rerun over `" << other
       << "`, is written to `plan-2.txt` and not run yet: run its commands like those of "
          "`plan.txt`, then collect again.\n\n";
  else if (!info.stage1_complete)
    md << "Stage 2 of the plan (the cheapest methods rerun over `" << other
       << "`) is planned once every run of stage 1 is there.\n\n";
}

// Where runs were judged against a co-simulation reference: what that is.
void cosim_reference_note(std::ostringstream& md, const std::vector<StudyRun>& runs) {
  const bool cosim_judged = std::any_of(runs.begin(), runs.end(), [](const StudyRun& r) {
    return r.record.reference_kind == "co-simulation";
  });
  if (cosim_judged)
    md << "Runs with a participant served by a node given by address (`--node`) or a soil of "
          "its own that the study starts (the FE soil, the Green's-function soil, an FMU the "
          "scene maps) are judged, and "
          "charted, against the co-simulation reference of the same participants (implicit "
          "coupling converged tightly at the sweep's smallest macro step; its own error a "
          "Richardson estimate, in each run's `summary.json`), not the monolithic model, which "
          "cannot stand for a participant's own physics; their ρ is measured through the "
          "participants' save and restore (matrix-free) where the map cannot be built.\n\n";
}

// What the report's errors are measured against, after the scene's line.
void errors_sentence(std::ostringstream& md, const std::vector<StudyRun>& runs,
                     double converged_tolerance) {
  if (reference_words(runs) == "the co-simulation reference")
    md << "Errors are relative L2 norms of the rail deflection at t_end against the co-simulation "
          "reference of each run's participants (see below); the study plans no monolithic run, "
          "whose built-in physics need not be theirs.\n\n";
  else
    md << "Errors are relative L2 norms of the rail deflection at t_end against the monolithic "
          "run with the same H and tolerance; the speed/accuracy chart measures every run "
          "against a converged monolithic run (tolerance "
       << converged_tolerance << " m) instead.\n\n";
}

}  // namespace

void write_report(const StudyReportInfo& info, const std::vector<StudyRun>& runs) {
  const std::string script = figure_script(info.figure_script);
  const bool swept = !info.sweeps.empty();
  const Scene base = load_scene((info.dir / "scene.toml").string());

  std::ostringstream md;
  md << "# Study of the `" << base.name << "` scene\n\n";
  md << "Scene file `" << info.source_scene << "` (copied to `scene.toml`): " << scene_line(base)
     << ". Co-simulation runs over `" << info.transport << "`. ";
  errors_sentence(md, runs, info.converged_tolerance);
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
  cosim_reference_note(md, runs);
  if (swept) incomplete_section(md, info, runs);

  for (const auto& [label, vdir] : info.variants) {
    std::vector<StudyRun> vr;  // folders relative to the variant's, as figures.py reads them
    for (const StudyRun& r : runs)
      if (r.variant == label) {
        vr.push_back(r);
        if (!vdir.empty()) vr.back().folder = r.folder.substr(vdir.size() + 1);
      }
    // front.csv first: the figures draw the report's answer from it.
    write_front_csv(info.dir / vdir / "front.csv", study_front(vr, info.transport));
    if (const auto slopes = error_slopes(vr); !slopes.empty())
      write_slopes_csv(info.dir / vdir / "error_slopes.csv", slopes);
    if (swept) {
      write_summary_csv(info.dir / vdir / "summary.csv", vr);
      const std::string note = draw_figures(info.dir / vdir, script);
      const Scene scene = load_scene((info.dir / vdir / "scene.toml").string());
      md << "## " << label << "\n\nScene variant `" << vdir << "/scene.toml`: " << scene_line(scene)
         << ".\n\n";
      write_answer(md, study_front(vr, info.transport), info.transport);
      scene_sections(md, "###", scene, vr, info.transport, vdir + "/figures", note,
                     info.dir / vdir);
      md << "\n";
    } else {
      const std::string note = draw_figures(info.dir, script);
      write_answer(md, study_front(vr, info.transport), info.transport);
      incomplete_section(md, info, runs);
      scene_sections(md, "##", base, vr, info.transport, "figures", note, info.dir);
    }
  }

  md << "\n## Every run\n\n| folder |" << (swept ? " variant |" : "")
     << " case | feedthrough | H (s) | tolerance (m) | wall (s) | micro steps | rel. L2 error | "
        "error vs converged | status |\n|---|"
     << (swept ? "---|" : "") << "---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : runs) {
    const run::RunRecord& x = r.record;
    long micro = 0;
    for (const auto& [k, v] : x.micro_steps) micro += v;
    const bool has = charted(x);
    md << "| " << r.folder << " | " << (swept ? r.variant + " | " : "") << x.case_name << " | "
       << x.feedthrough.value_or("–") << " | " << x.macro_step << " | " << r.tolerance << " | "
       << run::sci(x.wall_s) << " | " << micro << " | "
       << (x.rel_l2_error ? run::sci(*x.rel_l2_error) : "–") << " | "
       << (has ? run::sci(r.rel_l2_error_converged) : "–") << " | "
       << remote::markdown_text(x.status)
       << (x.status == "ok" || x.message.empty() ? ""
                                                 : " (" + remote::markdown_text(x.message) + ")")
       << " |\n";
  }
  run::write_file_atomically(info.dir / "REPORT.md", md.str());  // checked: never a 0-byte report
}

}  // namespace railcosim::study
