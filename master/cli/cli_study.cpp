#include "cli/cli_study.hpp"

#include "cli/cli.hpp"

#include "engine/coupling_options.hpp"
#include "remote/peer_text.hpp"

#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "auth.hpp"
#include "cli/conform.hpp"
#include "cosim_case.hpp"
#include "log.hpp"
#include "model.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "run/run_output.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "study/report.hpp"
#include "study/study.hpp"
#include "study/study_plan.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/stability.hpp"

namespace railcosim::cli {
namespace {

// Prints what a collection found; the exit status: 0 complete, 1 runs
// missing or failed, 3 only stage 2 of the plan left to run.
int report_collected(const study::CollectedStudy& c, const std::filesystem::path& out,
                     const std::string& what, double wall) {
  std::printf("%s: %zu runs in %.1f s (%d failed, %d missing, %d not run (budget))\n", what.c_str(),
              c.runs.size(), wall, c.failed, c.missing, c.not_run);
  for (const study::Finding& f : study::check_findings(c.runs))
    std::printf("  %-18s %s\n", f.verdict.c_str(), f.claim.c_str());
  std::printf("report: %s\n", (out / "REPORT.md").string().c_str());
  for (const auto& r : c.runs)
    if (r.record.status == "failed" || r.record.status == "missing" || r.record.status == "not_run")
      std::fprintf(stderr, "master: %s %s: %s\n", r.folder.c_str(),
                   remote::terminal_text(r.record.status).c_str(),
                   remote::terminal_text(r.record.message).c_str());
  if (c.failed + c.missing + c.not_run > 0) return 1;
  if (c.stage2_pending) {
    std::fprintf(stderr,
                 "master: stage 2 (the cheapest methods over the other transport) is planned in "
                 "%s: run it, then collect again\n",
                 study::plan_file(out, 2).string().c_str());
    return 3;
  }
  return 0;
}

}  // namespace

int do_study(const StudyArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  if (!a.collect.empty()) {
    if (a.check) {
      std::printf("check: would collect the study in %s\n", a.collect.c_str());
      return 0;
    }
    const study::CollectedStudy c = study::collect_study(a.collect, "");
    return report_collected(c, a.collect, "collected " + a.collect, seconds());
  }
  if (a.scene_path.empty()) throw std::invalid_argument("study: --scene FILE is required");
  study::StudyOptions o;
  o.out = a.out;
  o.jobs =
      a.jobs > 0 ? a.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  o.transport = a.transport;
  o.tolerances = a.tolerances;
  o.macro_steps = a.macro_steps;
  o.nodes = a.nodes;
  o.budget_s = a.budget;
  o.cases = a.cases;
  for (const std::string& s : a.sweeps) o.sweeps.push_back(study::parse_sweep(s));
  o.stop = stop_flag();
  if (!a.plan.empty() || a.check) {
    std::error_code ec;
    o.master_program =
        !a.master.empty() ? a.master : std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (o.master_program.empty()) o.master_program = "master";
    const study::StudyPlan plan = study::make_plan(a.scene_path, o);
    if (a.check) {
      std::printf("check: would %s %zu runs of %s into %s\n",
                  a.plan.empty() ? "run" : ("plan (" + a.plan + ")").c_str(), plan.runs.size(),
                  a.scene_path.c_str(), o.out.string().c_str());
      return 0;
    }
    study::write_plan(plan, a.plan);
    std::printf("plan: %zu runs in %s (and %s); run them, then master study --collect %s\n",
                plan.runs.size(), a.plan.c_str(), study::plan_file(o.out, 1).string().c_str(),
                o.out.string().c_str());
    return 0;
  }
  const study::CollectedStudy c = study::run_study(a.scene_path, o);
  return report_collected(c, o.out, "study of " + a.scene_path, seconds());
}

void add_study_command(CLI::App& app, StudyArgs& a) {
  CLI::App* study = app.add_subcommand(
      "study",
      "Run the whole study of a scene: every case, a macro-step sweep per method, the "
      "monolithic run across tolerances; write summary.csv, figures/ and REPORT.md");
  study->add_option("--scene", a.scene_path, "Scene file (TOML); required unless --collect")
      ->check(CLI::ExistingFile);
  study->add_option("--out", a.out, "Output folder")->capture_default_str();
  study->add_option("--jobs", a.jobs, "Runs in parallel (default: the number of cores)")
      ->check(CLI::PositiveNumber);
  study
      ->add_option(
          "--macro-steps", a.macro_steps,
          "Macro steps of the sweep, s (default: 1e-5 ... 1e-3, those dividing the end time)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  study->add_option("--tolerances", a.tolerances, "Tolerances of the monolithic reference curve, m")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  study->add_option("--transport", a.transport, "inproc or tcp (nodes started by the study)")
      ->check(CLI::IsMember(remote::transport_names()))
      ->capture_default_str();
  study->add_option("--sweep", a.sweeps,
                    "KEY=V1,V2,...: a scene value (dotted TOML key, e.g. vehicle.speed_kmh) and "
                    "its values, each a scene variant of its own; repeatable (cartesian product)");
  study->add_option("--node", a.nodes,
                    "ROLE=HOST:PORT: a participant served by a node already running (e.g. an "
                    "outside soil); repeatable. The study keeps the methods that have every "
                    "given role, runs them over tcp one at a time and judges each against its "
                    "co-simulation reference");
  study
      ->add_option("--budget", a.budget,
                   "The most the study may take, in seconds: a run not started within it is "
                   "written \"not run (budget)\" and listed in the report (default: no limit)")
      ->check(CLI::PositiveNumber);
  study
      ->add_option("--cases", a.cases,
                   "NAME,...: study only these co-simulation cases (each with its feedthrough "
                   "and coupling variants; default: every case of the scene)")
      ->delimiter(',');
  auto* plan_opt = study->add_option(
      "--plan", a.plan,
      "Write the study's runs to FILE, one `master run` command per line, without running them");
  auto* collect_opt =
      study
          ->add_option("--collect", a.collect,
                       "Read the run folders of the plan in DIR and write summary.csv, figures "
                       "and REPORT.md; exit 1 if runs are missing or failed")
          ->check(CLI::ExistingDirectory);
  collect_opt->excludes(plan_opt);
  study->add_option("--master", a.master,
                    "With --plan: the master program the command lines call (default: this one)");
  add_check_flag(*study, a.check);
  add_verbose_flag(*study);
  a.command = study;
}

}  // namespace railcosim::cli
