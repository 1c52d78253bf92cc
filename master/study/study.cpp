#include "study/study.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>

#include "connection.hpp"
#include "log.hpp"
#include "model.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "run/execute.hpp"
#include "run/progress.hpp"
#include "run/run_output.hpp"
#include "run/runner.hpp"
#include "study/report.hpp"
#include "study/report_methods.hpp"
#include "study/study_plan.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/reference.hpp"
#include "verdict/stability.hpp"

namespace railcosim::study {
namespace {}  // namespace

using run::execute;
using run::format_double;
using run::run_monolithic;
using run::RunJob;
using run::RunOptions;
using run::RunOutcome;
using run::RunRecord;
using run::write_file_atomically;
using verdict::ran_to_end;

std::string Method::label() const {
  std::string s = spec.name();
  if (feedthrough == Feedthrough::kResolved) s += "-resolved";
  if (!coupling.is_plain()) {
    s += '+';
    s += coupling.label();
  }
  for (const auto& [cut, k] : cut_windows)
    if (k > 1) s += "+" + cut + "-at-" + std::to_string(k) + "H";
  return s;
}

std::map<std::string, long> scene_cut_windows(const Scene& scene) {
  std::map<std::string, long> w;
  const SceneCoupling& c = scene.coupling;
  const std::pair<const char*, const std::optional<double>*> keys[] = {
      {"wr", &c.wr_macro_step}, {"rs", &c.rs_macro_step}, {"ss", &c.ss_macro_step}};
  for (const auto& [cut, value] : keys) {
    if (!value->has_value()) continue;
    const double k = **value / scene.macro_step;
    if (std::round(k) >= 2 && std::abs(k - std::round(k)) <= 1e-9 * k) w[cut] = std::lround(k);
  }
  return w;
}

namespace {

std::vector<Method> methods_of(const std::vector<std::string>& names) {
  std::vector<Method> m;
  for (const std::string& n : names) {
    if (n == "monolithic") continue;
    const CaseSpec c = parse_case(n);
    m.push_back({c, Feedthrough::kLagged, {}, {}});
    if (c.scheme == Scheme::kJacobi && c.has_force_feedthrough())
      m.push_back({c, Feedthrough::kResolved, {}, {}});
  }
  return m;
}

}  // namespace

std::vector<Method> all_methods() {
  return methods_of(paper_case_names());
}

std::vector<Method> methods_for(const Scene& scene) {
  std::vector<Method> m = methods_of(case_names(scene));
  const std::size_t plain = m.size();
  for (std::size_t k = 0; k < plain; ++k) {
    const Method& base = m[k];
    if (base.spec.cuts.size() != 1 || base.spec.scheme != Scheme::kJacobi ||
        base.feedthrough != Feedthrough::kLagged)
      continue;
    Method implicit = base;
    implicit.coupling.method = engine::CouplingMethod::kImplicit;
    implicit.coupling.inputs = engine::InputMode::kLinear;
    implicit.coupling.accelerator.kind = engine::AcceleratorKind::kIqnIls;
    Method extrapolated = base;
    extrapolated.coupling.inputs = engine::InputMode::kExtrapolate1;
    // The same implicit coupling with each sender's micro-step outputs as a
    // cubic waveform (in process only: run_transport()).
    Method waveform = implicit;
    waveform.coupling.inputs = engine::InputMode::kWaveform3;
    m.push_back(implicit);
    m.push_back(extrapolated);
    m.push_back(waveform);
  }
  // Multirate: the lagged methods of the cases with the cut, at its window.
  for (const auto& window : scene_cut_windows(scene))
    for (std::size_t i = 0; i < plain; ++i) {
      const std::string& cut = window.first;  // named: a lambda below captures it
      const Method& base = m[i];
      const bool has =
          std::any_of(base.spec.cuts.begin(), base.spec.cuts.end(), [&cut](const CutChoice& c) {
            return cut_kinds()[static_cast<std::size_t>(c.cut)].name == cut;
          });
      if (!has || base.feedthrough != Feedthrough::kLagged) continue;
      Method multi = base;
      multi.cut_windows[cut] = window.second;
      m.push_back(multi);
    }
  return m;
}

std::vector<Method> methods_with_nodes(const Scene& scene, const std::vector<Method>& methods,
                                       const std::vector<std::string>& nodes) {
  std::vector<std::string> roles;
  for (const std::string& n : nodes) {
    const auto eq = n.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--node " + n +
                                  ": expected ROLE=HOST:PORT, e.g. soil=127.0.0.1:7003");
    parse_address(n.substr(eq + 1), "--node " + n.substr(0, eq));
    roles.push_back(n.substr(0, eq));
  }
  std::vector<Method> kept;
  std::set<std::string> seen;
  for (const Method& m : methods) {
    std::set<std::string> has;
    for (const auto& p : partition(scene, m.spec)) has.insert(p.role);
    seen.insert(has.begin(), has.end());
    const bool all = std::all_of(roles.begin(), roles.end(),
                                 [&has](const std::string& r) { return has.count(r) != 0; });
    if (all && engine::waveform_degree(m.coupling.inputs) < 0) kept.push_back(m);
  }
  for (const std::string& r : roles)
    if (seen.count(r) == 0) {
      std::string there;
      for (const std::string& x : seen) there += (there.empty() ? "" : ", ") + x;
      throw std::invalid_argument("--node " + r + "=...: no case of the scene has a " + r +
                                  " participant (its participants: " + there + ")");
    }
  if (kept.empty())
    throw std::invalid_argument("--node: no case of the scene has every participant given");
  return kept;
}

std::string run_transport(const engine::CouplingOptions& coupling, const std::string& transport) {
  return engine::waveform_degree(coupling.inputs) >= 0 ? remote::kInprocTransport : transport;
}

std::vector<double> default_macro_steps(const Scene& scene) {
  std::vector<double> out;
  for (double H : {1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3}) {
    const double n = scene.end_time / H;
    if (std::abs(n - std::round(n)) <= 1e-9 * n && n >= 1) out.push_back(H);
  }
  if (std::find(out.begin(), out.end(), scene.macro_step) == out.end()) {
    out.push_back(scene.macro_step);
    std::sort(out.begin(), out.end());
  }
  return out;
}

bool charted(const RunRecord& r) {
  return ran_to_end(r) && (r.reference_kind != "co-simulation" || r.rel_l2_error.has_value());
}

void write_summary_csv(const std::filesystem::path& file, const std::vector<StudyRun>& runs) {
  std::ostringstream f;  // written whole, checked, at the end
  f << "group,folder,method,case,split,coupling,scheme,feedthrough,macro_step_s,tolerance_m,"
       "t_end_s,wall_s,macro_steps,micro_steps_monolithic,micro_steps_s1,micro_steps_s2,status,"
       "max_abs_error_m,rel_l2_error,history_error,rel_l2_error_converged,transport,message,"
       "coupling_method,inputs,accelerator,iterations_mean,iterations_max,restart,variant,"
       "stability,error_growth,rho,rho_rate_per_s,rho_basis,reference_kind,reference_folder\n";
  auto opt = [](const std::optional<std::string>& s) { return s ? *s : std::string(); };
  auto optd = [](const std::optional<double>& v) { return v ? format_double(*v) : std::string(); };
  auto steps = [](const RunRecord& r, const char* k) {
    const auto it = r.micro_steps.find(k);
    return it == r.micro_steps.end() ? std::string() : std::to_string(it->second);
  };
  auto quoted = [](std::string s) {
    for (auto& c : s)
      if (c == '"' || c == '\n') c = '\'';
    return "\"" + s + "\"";
  };
  for (const StudyRun& s : runs) {
    const RunRecord& r = s.record;
    f << s.group << "," << s.folder << "," << s.method << "," << r.case_name << "," << opt(r.split)
      << "," << opt(r.coupling) << "," << opt(r.scheme) << "," << opt(r.feedthrough) << ","
      << format_double(r.macro_step) << "," << format_double(s.tolerance) << ","
      << format_double(r.t_end) << "," << format_double(r.wall_s) << "," << r.macro_steps << ","
      << steps(r, "monolithic") << "," << steps(r, "s1") << "," << steps(r, "s2") << "," << r.status
      << "," << optd(r.max_abs_error_m) << "," << optd(r.rel_l2_error) << ","
      << optd(r.history_error) << ","
      << (charted(r) ? format_double(s.rel_l2_error_converged) : std::string()) << ","
      << r.transport << "," << quoted(r.message) << "," << r.method << "," << r.inputs << ","
      << opt(r.accelerator) << "," << optd(r.iterations_mean) << ","
      << (r.iterations_max ? std::to_string(*r.iterations_max) : std::string()) << "," << r.restart
      << "," << s.variant << "," << r.stability << "," << optd(r.error_growth) << ","
      << optd(rho_of(r)) << "," << optd(rho_rate_of(r)) << "," << rho_basis_of(r) << ","
      << r.reference_kind << "," << r.reference_folder << "\n";
  }
  write_file_atomically(file, f.str());
}

namespace {

// The plan's "ROLE=HOST:PORT" entries (checked by make_plan()) by role.
std::map<std::string, Address> given_nodes(const std::vector<std::string>& nodes) {
  std::map<std::string, Address> given;
  for (const std::string& n : nodes) {
    const auto eq = n.find('=');
    given[n.substr(0, eq)] = parse_address(n.substr(eq + 1), "--node " + n.substr(0, eq));
  }
  return given;
}

// Writes the folder of a run the study's budget left no time for: status
// "not_run", and why, so that the report lists it.
void write_not_run(const StudyPlan& plan, const PlannedRun& run, const Scene& scene,
                   double budget_s) {
  RunOptions o;
  o.macro_step = run.macro_step;
  o.tolerance = run.tolerance;
  o.feedthrough = run.feedthrough;
  o.coupling = run.coupling;
  RunRecord r =
      run::failed_record(scene, parse_case(run.case_name), o, run.transport,
                         "not run (budget): the study's budget of " + format_double(budget_s) +
                             " s (--budget) was spent before this run could start");
  r.status = "not_run";
  run::RunWriter w(plan.out / std::filesystem::path(run.folder).parent_path(), run.case_name);
  w.finish(r);
}

// A monolithic reference, computed once by whichever worker needs it first.
struct Reference {
  std::once_flag once;
  RunRecord record;
};

// What the workers of a plan share: its scenes by file, and the monolithic
// references by scene file, H and tolerance.
struct PlanScenes {
  std::map<std::string, Scene> scenes;
  std::map<std::tuple<std::string, double, double>, Reference> references;
  verdict::CosimReferences cosim;  // the co-simulation references of a case, made once
};

// Runs one planned run with the worker's nodes and writes its folder (see
// execute()); the monolithic reference of its scene, H and tolerance is
// computed once, by whichever worker needs it first.
void execute_run(const StudyPlan& plan, const StudyOptions& opt, const PlannedRun& run,
                 remote::NodePool& pool, PlanScenes& shared,
                 std::function<void(long, long)> on_progress) {
  const Scene& scene = shared.scenes.at(run.scene);
  RunJob job;
  job.scene = &scene;
  job.spec = parse_case(run.case_name);
  job.options.macro_step = run.macro_step;
  job.options.tolerance = run.tolerance;
  job.options.feedthrough = run.feedthrough;
  job.options.coupling = run.coupling;
  // A multirate method's cuts at their windows, as its plan line says.
  job.options.cut_windows = run.cut_windows;
  job.options.stop = opt.stop;
  job.transport = run.transport;
  job.nodes = {given_nodes(plan.nodes), &pool, {}, {}};
  job.reference_step = run.reference_step;
  job.cosim_references = &shared.cosim;
  job.out = plan.out / std::filesystem::path(run.folder).parent_path();
  job.folder = run.case_name;
  job.on_progress = std::move(on_progress);
  job.reference = [&]() -> const RunRecord& {
    Reference& ref = shared.references.at({run.scene, run.macro_step, run.tolerance});
    std::call_once(ref.once, [&] {
      RunOptions m;
      m.macro_step = run.macro_step;
      m.tolerance = run.tolerance;
      ref.record = run_monolithic(scene, m);
    });
    return ref.record;
  };
  const RunOutcome outcome = execute(job);
  if (!outcome.error.empty()) logger("master")->error("{} failed: {}", run.folder, outcome.error);
}

// Runs a plan here, JOBS at a time, each worker with its own nodes. Each run
// writes what `master run` with the plan's command line writes: the same
// options, the same reference (the monolithic run of its scene at its H and
// tolerance), the same folder.
void execute_plan(const StudyPlan& plan, const StudyOptions& opt,
                  std::chrono::steady_clock::time_point deadline) {
  PlanScenes shared;
  shared.cosim.write_below(plan.out);
  for (const PlannedRun& r : plan.runs)
    if (!shared.scenes.count(r.scene))
      shared.scenes.emplace(r.scene, load_scene((plan.out / r.scene).string()));
  for (const PlannedRun& r : plan.runs)
    if (r.case_name != "monolithic") shared.references[{r.scene, r.macro_step, r.tolerance}];

  const std::size_t total = plan.runs.size();
  const int workers = std::max(1, std::min<int>(opt.jobs, static_cast<int>(total)));
  std::vector<remote::NodePool> pools(static_cast<std::size_t>(workers));
  // A soil the study starts (FE, Green's functions): one per worker, kept for
  // its runs; it writes no measures (its reference runs would overwrite them).
  for (const auto& [file, scene] : shared.scenes)
    if (scene.started_soil() != nullptr && given_nodes(plan.nodes).count("soil") == 0)
      for (remote::NodePool& pool : pools)
        pool.use_fe_soil({scene.soil_ranks, "", scene.started_soil(), scene.source});
  logger("master")->info("study of {}, stage {}: {} runs on {} worker(s)", plan.source_scene,
                         plan.stage, total, workers);
  std::atomic<std::size_t> next{0};
  run::Progress progress("study, stage " + std::to_string(plan.stage), static_cast<long>(total),
                         workers);
  auto work = [&](int w) {
    for (std::size_t j; (j = next++) < total;) {
      const std::string& folder = plan.runs[j].folder;
      if (opt.budget_s > 0 && std::chrono::steady_clock::now() >= deadline) {
        try {
          write_not_run(plan, plan.runs[j], shared.scenes.at(plan.runs[j].scene), opt.budget_s);
        } catch (const std::exception& e) {
          logger("master")->error("{}: not run (budget), and no summary written: {}", folder,
                                  e.what());
        }
        progress.run_done(w);
        continue;
      }
      execute_run(plan, opt, plan.runs[j], pools[static_cast<std::size_t>(w)], shared,
                  [&progress, w, &folder](long done, long steps) {
                    progress.step(w, folder, done, steps);
                  });
      progress.run_done(w);
    }
  };
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(work, w);
  for (auto& t : threads) t.join();
  progress.end();
}

}  // namespace

CollectedStudy run_study(const std::string& scene_path, const StudyOptions& opt) {
  check_study_scene(load_scene(scene_path), opt);
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(opt.budget_s));
  std::error_code ec;
  std::filesystem::remove(plan_file(opt.out, 2), ec);  // stage 2 follows from this stage 1
  StudyOptions o = opt;
  if (!o.nodes.empty()) {
    if (!remote::is_remote_transport(o.transport))
      throw std::invalid_argument(
          "--node needs --transport tcp (the given nodes are reached "
          "over TCP), not --transport " +
          o.transport);
    o.jobs = 1;  // a node serves one session at a time
  }
  const StudyPlan plan = make_plan(scene_path, o);
  write_plan(plan);
  execute_plan(plan, o, deadline);
  // Collecting stage 1 writes stage 2 (it needs stage 1's wall times).
  const CollectedStudy first = collect_study(opt.out, opt.figure_script, false);
  if (first.stage2_pending && !(opt.stop && opt.stop->load() != 0)) {
    StudyPlan second = read_plan(plan_file(opt.out, 2));
    second.out = opt.out;
    StudyOptions one = opt;
    one.jobs = 1;  // one at a time, so that their wall times compare with stage 1's
    execute_plan(second, one, deadline);
  }
  return collect_study(opt.out, opt.figure_script);
}

}  // namespace railcosim::study
