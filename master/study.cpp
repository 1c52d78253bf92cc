#include "study.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "evaluation.hpp"
#include "log.hpp"
#include "node_launcher.hpp"
#include "remote_participant.hpp"
#include "report.hpp"
#include "report_methods.hpp"
#include "run_output.hpp"
#include "runner.hpp"
#include "transport.hpp"

namespace railcosim {
namespace {

std::string short_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A unit of work for a worker.
struct Job {
  std::size_t index;  // into the runs
  bool monolithic;
  Method method;
  RunOptions options;
  std::shared_ptr<const Scene> scene;          // null: the study's scene
  std::shared_ptr<const RunRecord> reference;  // null: the monolithic run at the same H
  std::string transport;                       // empty: the study's transport
};

}  // namespace

std::string Method::label() const {
  std::string s = spec.name();
  if (feedthrough == Feedthrough::kResolved) s += "-resolved";
  if (!coupling.is_plain()) {
    s += '+';
    s += coupling.label();
  }
  return s;
}

namespace {

std::vector<Method> methods_of(const std::vector<std::string>& names) {
  std::vector<Method> m;
  for (const std::string& n : names) {
    if (n == "monolithic") continue;
    const CaseSpec c = parse_case(n);
    m.push_back({c, Feedthrough::kLagged, {}});
    if (c.scheme == Scheme::kJacobi && c.has_force_feedthrough())
      m.push_back({c, Feedthrough::kResolved, {}});
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
    implicit.coupling.method = CouplingMethod::kImplicit;
    implicit.coupling.inputs = InputMode::kLinear;
    implicit.coupling.accelerator.kind = AcceleratorKind::kIqnIls;
    Method extrapolated = base;
    extrapolated.coupling.inputs = InputMode::kExtrapolate1;
    m.push_back(implicit);
    m.push_back(extrapolated);
  }
  return m;
}

namespace {

// The paper's "Gauss–Seidel divides the Jacobi error by almost 10" at the
// rail/sleepers cut with X-X, under both restart conventions, with 10 fixed
// micro steps per macro step of 1e-4 s (as the paper's solver would take).
template <class Add>
void add_restart_check(const Scene& scene, const StudyOptions& opt, Add add) {
  const auto names = case_names(scene);
  const double H = 1e-4;
  const double n = scene.end_time / H;
  if (!opt.restart_check || std::find(names.begin(), names.end(), "rs-xx-jacobi") == names.end() ||
      std::abs(n - std::round(n)) > 1e-9 * n)
    return;
  auto fixed = std::make_shared<Scene>(scene);
  fixed->micro_steps = 10;
  RunOptions o;
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  auto reference = std::make_shared<const RunRecord>(run_monolithic(*fixed, o));
  for (const char* restart : {"consistent", "carry"}) {
    auto sc = std::make_shared<Scene>(*fixed);
    sc->restart = restart;
    for (const char* c : {"rs-xx-jacobi", "rs-xx-gauss-seidel"}) {
      Method m;
      m.spec = parse_case(c);
      std::string folder = "restart/";
      folder += restart;
      folder += '/';
      folder += c;
      Job& j = add("restart", folder, false, m, H, scene.tolerance);
      j.scene = sc;
      j.reference = reference;
    }
  }
}

}  // namespace

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

void write_summary_csv(const std::filesystem::path& file, const std::vector<StudyRun>& runs) {
  std::ostringstream f;  // written whole, checked, at the end
  f << "group,folder,method,case,split,coupling,scheme,feedthrough,macro_step_s,tolerance_m,"
       "t_end_s,wall_s,macro_steps,micro_steps_monolithic,micro_steps_s1,micro_steps_s2,status,"
       "max_abs_error_m,rel_l2_error,history_error,rel_l2_error_converged,transport,message,"
       "coupling_method,inputs,accelerator,iterations_mean,iterations_max,restart\n";
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
      << (r.status == "ok" || r.status == "amplified" ? format_double(s.rel_l2_error_converged)
                                                      : std::string())
      << "," << r.transport << "," << quoted(r.message) << "," << r.method << "," << r.inputs << ","
      << opt(r.accelerator) << "," << optd(r.iterations_mean) << ","
      << (r.iterations_max ? std::to_string(*r.iterations_max) : std::string()) << "," << r.restart
      << "\n";
  }
  write_file_atomically(file, f.str());
}

namespace {

// The cheapest method at each accuracy level, run again over the other
// transport (in-process for a TCP study, and the reverse), one at a time so
// that the wall times are comparable.
void rerun_cheapest_in_other_transport(const Scene& scene, const StudyOptions& opt,
                                       const std::vector<Job>& jobs, std::vector<StudyRun>& runs) {
  if (opt.stop && opt.stop->load() != 0) return;
  const std::string other = opt.transport == "tcp" ? "inproc" : "tcp";
  NodePool pool;
  const Transport t = other == "tcp" ? tcp_transport(scene, {}, pool) : inproc_transport(scene);
  std::vector<std::size_t> done;
  for (double level : accuracy_levels()) {
    const StudyRun* best = cheapest_reaching(runs, level);
    if (!best) continue;
    const auto index = static_cast<std::size_t>(best - runs.data());
    if (std::find(done.begin(), done.end(), index) != done.end()) continue;
    done.push_back(index);
    const auto job =
        std::find_if(jobs.begin(), jobs.end(), [&](const Job& j) { return j.index == index; });
    if (job == jobs.end()) continue;
    StudyRun s;
    s.group = "other-transport";
    s.method = best->method;
    s.tolerance = best->tolerance;
    s.folder = "other-transport/" + other + "/H_" + short_number(job->options.macro_step) + "/" +
               best->method;
    try {
      RunWriter writer(opt.out, s.folder);
      RunOptions o = job->options;
      o.stop = opt.stop;
      s.record = run_cosim(scene, job->method.spec, o, t.factory, t.name);
      s.record.rel_l2_error = best->record.rel_l2_error;  // the same run, bitwise
      writer.finish(s.record);
    } catch (const std::exception& e) {
      s.record = failed_record(scene, job->method.spec, job->options, other, e.what());
    }
    runs.push_back(std::move(s));
  }
}

}  // namespace

std::vector<StudyRun> run_study(const Scene& scene, const StudyOptions& opt) {
  auto log = logger("master");
  std::filesystem::create_directories(opt.out);
  const std::vector<double> sweep =
      opt.macro_steps.empty() ? default_macro_steps(scene) : opt.macro_steps;

  // The plan: runs at the scene's H (the cases), the sweep, the tolerances.
  const std::vector<Method> methods = opt.methods.empty() ? methods_for(scene) : opt.methods;
  std::vector<StudyRun> runs;
  std::vector<Job> jobs;
  auto add = [&](const std::string& group, const std::string& folder, bool mono, const Method& m,
                 double H, double tol) -> Job& {
    StudyRun s;
    s.group = group;
    s.folder = folder;
    s.method = mono ? "monolithic" : m.label();
    s.tolerance = tol;
    RunOptions o;
    o.macro_step = H;
    o.tolerance = tol;
    o.feedthrough = m.feedthrough;
    o.coupling = m.coupling;
    jobs.push_back({runs.size(), mono, m, o, nullptr, nullptr, {}});
    runs.push_back(std::move(s));
    return jobs.back();
  };
  add("case", "monolithic", true, {}, scene.macro_step, scene.tolerance);
  for (const Method& m : methods)
    add("case", m.label(), false, m, scene.macro_step, scene.tolerance);
  for (double H : sweep) {
    if (H == scene.macro_step) continue;  // the cases are that column of the sweep
    for (const Method& m : methods)
      if (m.coupling.method != CouplingMethod::kImplicit || H >= opt.implicit_min_macro_step)
        add("sweep", "sweep/H_" + short_number(H) + "/" + m.label(), false, m, H, scene.tolerance);
  }
  add_restart_check(scene, opt, add);
  for (double tol : opt.tolerances)
    add("tolerance", "sweep/tol_" + short_number(tol) + "/monolithic", true, {}, scene.macro_step,
        tol);

  // Monolithic references, one per macro step, and the converged one.
  std::map<double, RunRecord> references;
  {
    std::vector<double> steps = sweep;
    steps.push_back(scene.macro_step);
    std::sort(steps.begin(), steps.end());
    steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
    std::vector<std::thread> threads;
    std::mutex mutex;
    for (double H : steps)
      threads.emplace_back([&, H] {
        RunOptions o;
        o.macro_step = H;
        o.tolerance = scene.tolerance;
        RunRecord r = run_monolithic(scene, o);
        std::lock_guard lock(mutex);
        references[H] = std::move(r);
      });
    for (auto& t : threads) t.join();
  }
  RunOptions conv;
  conv.macro_step = scene.macro_step;
  conv.tolerance = opt.converged_tolerance;
  const RunRecord converged = run_monolithic(scene, conv);

  // Workers: each owns a node per participant role, serving its runs one
  // after another.
  const int workers = std::max(1, std::min<int>(opt.jobs, static_cast<int>(jobs.size())));
  std::vector<NodePool> pools(static_cast<std::size_t>(workers));
  log->info("study of {}: {} runs on {} worker(s), transport {}", scene.source, jobs.size(),
            workers, opt.transport);

  std::atomic<std::size_t> next{0}, done{0};
  std::mutex out_mutex;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  auto work = [&](int w) {
    const Transport transport = opt.transport == "tcp"
                                    ? tcp_transport(scene, {}, pools[static_cast<std::size_t>(w)])
                                    : inproc_transport(scene);
    const ParticipantFactory& factory = transport.factory;
    for (std::size_t j; (j = next++) < jobs.size();) {
      const Job& job = jobs[j];
      StudyRun& s = runs[job.index];
      RunRecord r;
      const CaseSpec spec = job.monolithic ? CaseSpec{} : job.method.spec;
      try {
        RunWriter writer(opt.out, s.folder);
        RunOptions o = job.options;
        o.stop = opt.stop;
        o.on_row = [&writer](const HistoryRow& row) { writer.row(row); };
        o.on_channels = [&writer](const std::vector<std::string>& extra) {
          writer.channels(extra);
        };
        const Scene& sc = job.scene ? *job.scene : scene;
        if (job.monolithic) {
          r = run_monolithic(sc, o);
        } else {
          r = run_cosim(sc, spec, o, factory, opt.transport);
          judge(r, job.reference ? *job.reference : references.at(o.macro_step), sc);
        }
        if (r.status == "ok" || r.status == "amplified")
          s.rel_l2_error_converged = deflection_error(r.deflection, converged.deflection).rel_l2;
        writer.finish(r);
      } catch (const std::exception& e) {
        r = failed_record(scene, spec, job.options, opt.transport, e.what());
        log->error("{} failed: {}", s.folder, e.what());
        try {
          RunWriter(opt.out, s.folder).finish(r);
        } catch (const std::exception&) {
        }
      }
      s.record = std::move(r);
      const std::size_t d = ++done;
      if (tty) {
        std::lock_guard lock(out_mutex);
        std::fprintf(stderr, "\rstudy: %zu/%zu runs done   ", d, jobs.size());
        if (d == jobs.size()) std::fputs("\n", stderr);
      }
    }
  };
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(work, w);
  for (auto& t : threads) t.join();

  rerun_cheapest_in_other_transport(scene, opt, jobs, runs);

  write_summary_csv(opt.out / "summary.csv", runs);
  write_report(scene, opt, runs, converged);
  return runs;
}

}  // namespace railcosim
