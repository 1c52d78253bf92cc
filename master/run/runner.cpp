#include "run/runner.hpp"

#include <chrono>
#include <cmath>
#include <functional>
#include <sstream>

#include "engine/coupled_statics.hpp"
#include "engine/multirate.hpp"
#include "engine/schedule.hpp"
#include "engine/window_schedule.hpp"
#include "log.hpp"
#include "monolithic.hpp"
#include "remote/direct_exchange.hpp"
#include "remote/reply_check.hpp"
#include "remote/transport.hpp"
#include "run/coupling_history.hpp"
#include "run/step_loop.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim::run {

using engine::CouplingMethod;
using engine::MacroSteps;

using remote::DataPlane;
using remote::DirectExchange;
using remote::is_remote_transport;
using remote::ParticipantFactory;

namespace {

using Clock = std::chrono::steady_clock;

std::vector<double> rail_positions(const Scene& scene) {
  std::vector<double> x(static_cast<std::size_t>(scene.rail_nodes()));
  for (std::size_t k = 0; k < x.size(); ++k)
    x[k] = scene.rail_start + static_cast<double>(k) * scene.element_length();
  return x;
}

std::vector<double> sleeper_positions(const Scene& scene) {
  std::vector<double> x;
  for (double p : coupling_points(scene, find_cut("rs"))) x.push_back(scene.rail_start + p);
  return x;
}

long steps_to(const Scene& scene, double H) {
  return std::lround(scene.end_time / H);
}

// The iterations of an implicit run into its record; a run with macro steps
// that did not converge is not ok.
void record_convergence(RunRecord& r, const engine::ConvergenceLog& log, const RunOptions& o) {
  r.convergence_quantities = log.quantities;
  r.convergence = log.rows;
  long sum = 0, most = 0;
  for (int k : log.iterations) {
    sum += k;
    most = std::max<long>(most, k);
  }
  r.iterations_mean = log.iterations.empty()
                          ? 0.0
                          : static_cast<double>(sum) / static_cast<double>(log.iterations.size());
  r.iterations_max = most;
  r.not_converged_steps = log.not_converged;
  if (log.not_converged > 0 && r.status == "ok") {
    std::ostringstream s;
    s << log.not_converged << " of " << log.iterations.size()
      << " macro steps did not converge within " << o.coupling.max_iterations
      << " iterations (to a relative residual of " << o.coupling.convergence
      << "); the first at macro step " << log.first_not_converged + 1
      << " (t = " << static_cast<double>(log.first_not_converged + 1) * o.macro_step
      << " s): raise --max-iterations ([coupling] max_iterations) or loosen --convergence "
         "([coupling] convergence)";
    r.status = "not_converged";
    r.message = s.str();
  }
}

}  // namespace

RunRecord failed_record(const Scene& scene, const CaseSpec& spec, const RunOptions& o,
                        const std::string& transport, const std::string& why) {
  RunRecord r;
  r.case_name = spec.name();
  if (!spec.monolithic) {
    r.split = spec.split_name();
    r.coupling = spec.coupling_name();
    r.scheme = to_string(spec.scheme);
    r.feedthrough = to_string(o.feedthrough);
    r.transport = transport;
    r.method = to_string(o.coupling.method);
    r.inputs = to_string(o.coupling.inputs);
    if (o.coupling.method == CouplingMethod::kImplicit)
      r.accelerator = to_string(o.coupling.accelerator.kind);
    for (const CutChoice& c : spec.cuts) {  // each cut's window: H unless given its own
      const std::string cut = cut_kinds()[static_cast<std::size_t>(c.cut)].name;
      const auto w = o.cut_windows.find(cut);
      r.windows[cut] = o.macro_step * static_cast<double>(w == o.cut_windows.end() ? 1 : w->second);
    }
  }
  r.macro_step = o.macro_step;
  r.t_end = scene.end_time;
  r.status = "failed";
  r.message = why;
  return r;
}

RunRecord run_monolithic(const Scene& scene, const RunOptions& o) {
  const auto t0 = Clock::now();
  MonolithicModel model(scene, o.macro_step, o.tolerance);
  RunRecord r;
  r.case_name = "monolithic";
  r.macro_step = o.macro_step;
  r.t_end = scene.end_time;
  r.extra_channels = model.extra_channels();
  if (o.on_channels) o.on_channels(r.extra_channels);
  const long N = steps_to(scene, o.macro_step);
  r.history.reserve(static_cast<std::size_t>(N + 1));
  auto record_row = [&](const HistoryRow& row) {
    r.history.push_back(row);
    record_coupling(r, model);  // coupling_history.hpp: judged with the history
    if (o.on_row) o.on_row(row);
  };
  record_row(model.history_row(0));
  for (long n = 0; n < N; ++n) {
    check_stop(o, n);
    model.advance(n);
    record_row(model.history_row(n + 1));
    if (o.on_progress) o.on_progress(n + 1, N);
  }
  r.macro_steps = N;
  r.micro_steps["monolithic"] = model.integrator().state().micro_steps;
  r.x = rail_positions(scene);
  r.deflection = model.rail_deflection();
  r.soil = model.soil_deflection();
  if (!r.soil.empty()) r.soil_x = sleeper_positions(scene);
  if (scene.ballast_forces) r.sleeper_x = sleeper_positions(scene);
  r.max_abs_error_m = 0.0;
  r.rel_l2_error = 0.0;
  r.history_error = 0.0;
  r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

namespace {

// Maps the participants' declared history channels onto the history rows:
// the wheel's two channels into their fields, every other one into extra.
class HistoryAssembler {
 public:
  explicit HistoryAssembler(const std::vector<Participant*>& ps) {
    for (std::size_t p = 0; p < ps.size(); ++p) {
      const Channels c = ps[p]->channels();
      for (std::size_t k = 0; k < c.history.size(); ++k) {
        const std::string& name = c.history[k];
        int slot = -1;
        if (name == "wheel_m")
          slot = -2;
        else if (name == "contact_force_N")
          slot = -3;
        else {
          slot = static_cast<int>(extra_.size());
          extra_.push_back(name);
        }
        map_.push_back({p, k, slot});
      }
    }
  }
  const std::vector<std::string>& extra_names() const { return extra_; }

  HistoryRow row(double t, const std::vector<StepResult>& r,
                 const std::vector<Participant*>& ps) const {
    HistoryRow row;
    row.t = t;
    row.extra.assign(extra_.size(), 0.0);
    for (const auto& m : map_) {
      const auto& h = r[m.participant].history;
      if (m.index >= h.size())
        throw std::runtime_error(ps[m.participant]->name() + " reported " +
                                 std::to_string(h.size()) + " history value(s), fewer than the " +
                                 "channels it declared");
      const double v = h[m.index];
      if (m.slot == -2)
        row.wheel = v;
      else if (m.slot == -3)
        row.contact_force = v;
      else
        row.extra[static_cast<std::size_t>(m.slot)] = v;
    }
    return row;
  }

 private:
  struct Map {
    std::size_t participant, index;
    int slot;
  };
  std::vector<Map> map_;
  std::vector<std::string> extra_;
};

// The participants of a co-simulation in load order, their routing and
// their coupled static state (declared in the order they are torn down last).
struct Participants {
  std::vector<ParticipantSpec> specs;
  std::vector<std::unique_ptr<Participant>> owned;
  std::vector<Participant*> ps;
  engine::Routing routing;
  engine::RatePlan rates;
  engine::StaticsOutcome statics;
};

// Set-up: the case's participants, made by `make`, and their static state.
Participants start_participants(const Scene& scene, const CaseSpec& spec, const RunOptions& o,
                                const ParticipantFactory& make, const std::string& case_name) {
  Participants P;
  P.specs = partition(scene, spec);
  P.rates = rate_plan(scene, spec, o);
  check_whole_windows(scene, o, P.rates);
  for (std::size_t k = 0; k < P.specs.size(); ++k) {
    // A participant steps at its own window (multirate), else at H.
    const double H = o.macro_step * static_cast<double>(P.rates.window[k]);
    P.owned.push_back(make(subsystem_config(scene, P.specs[k], H, o.tolerance)));
    P.ps.push_back(P.owned.back().get());
  }
  P.routing = engine::make_routing(P.specs);
  std::vector<CouplingData> zero;
  for (const ParticipantSpec& p : P.specs) zero.push_back(engine::zero_inputs(scene, p));
  P.statics = engine::find_static_state(P.ps, P.routing, zero);
  logger("master")->debug("{}: static state after {} interface iterations (residual {})", case_name,
                          P.statics.iterations, P.statics.residual);
  return P;
}

// The direct data plane when the run asks for it on TCP: explicit coupling
// with held inputs in windows over peer links (returned), the couplings the
// master decides step by step (implicit, ramped) in lock step. Records the
// plane the run took.
// A multirate run goes in lock step (the nodes' windows run one rate), each
// participant to the end of its own windows; `plan` is null for it.
std::unique_ptr<DirectExchange> start_data_plane(RunRecord& r, const RunOptions& o,
                                                 const std::string& transport,
                                                 const Participants& P,
                                                 const engine::StepPlan* plan, double bound,
                                                 long N) {
  std::unique_ptr<DirectExchange> direct;
  bool lockstep = false;
  if (o.data_plane == DataPlane::kDirect && is_remote_transport(transport)) {
    // A node that offers neither is worth a word.
    const bool windows = plan && o.coupling.method == CouplingMethod::kExplicit &&
                         o.coupling.inputs == engine::InputMode::kHold;
    std::string why = remote::relay_reason(P.ps, !windows);
    if (windows)
      direct = DirectExchange::make(P.ps, *plan, bound, N, o.direct);
    else if (!plan && o.coupling.method == CouplingMethod::kImplicit)
      why =
          "a node keeps one checkpoint in lock step, and a multirate implicit step needs its "
          "slow window's and its fine windows'";
    else if (why.empty())
      for (std::size_t p = 0; p < P.ps.size(); ++p)
        lockstep = remote::enter_lockstep({P.ps[p]}, 0, N / P.rates.window[p]);
    if (!direct && !lockstep)
      logger("master")->info("{}: relayed data plane ({})", r.case_name, why);
    else if (lockstep)
      logger("master")->debug(
          "{}: direct data plane in lock step (the master decides every macro step)", r.case_name);
  }
  if (is_remote_transport(transport)) {
    r.data_plane = to_string(direct || lockstep ? DataPlane::kDirect : DataPlane::kRelay);
    if (direct || lockstep) r.data_plane_mode = direct ? "windows" : "lock step";
  }
  return direct;
}

// The record's completion: the participants' final results (none from a
// participant that gave up on a step) and the positions of the fields.
void complete_record(RunRecord& r, const Scene& scene, const Participants& P) {
  for (std::size_t p = 0; p < P.ps.size(); ++p) {
    ParticipantResults res;
    try {
      res = P.ps[p]->results();
    } catch (const std::exception& e) {
      // A participant that gave up on a step (diverged, or failed) is mid-step,
      // or has ended its session.
      if (r.status != "diverged" && r.status != "failed") throw;
      logger("master")->warn("{}: no final results after the run stopped: {}", r.case_name,
                             e.what());
    }
    std::string key = "s";  // s1, s2, ...: appended, which spares GCC 12 a false -Wrestrict
    key += std::to_string(p + 1);
    r.micro_steps[key] = res.micro_steps;
    const Channels c = P.ps[p]->channels();
    for (std::size_t k = 0; k < c.results.size() && k < res.fields.size(); ++k) {
      if (c.results[k] == "rail_w_m") r.deflection = res.fields[k];
      if (c.results[k] == "soil_m") r.soil = res.fields[k];
    }
  }
  r.x = rail_positions(scene);
  if (!r.soil.empty()) r.soil_x = sleeper_positions(scene);
  if (scene.ballast_forces) r.sleeper_x = sleeper_positions(scene);
}

}  // namespace

RunRecord run_cosim(const Scene& scene, const CaseSpec& spec, const RunOptions& o,
                    const ParticipantFactory& make, const std::string& transport) {
  const auto t0 = Clock::now();
  remote::check_transport(o.coupling, transport);  // before any node is started
  RunRecord r = failed_record(scene, spec, o, transport, "");
  r.status = "ok";
  r.restart = scene.restart;
  const Participants P = start_participants(scene, spec, o, make, r.case_name);

  remote::require_distinct_channels(P.ps);  // reply_check.hpp
  HistoryAssembler history(P.ps);
  r.extra_channels = history.extra_names();
  if (o.on_channels) o.on_channels(r.extra_channels);
  std::vector<std::string> roles;
  for (const ParticipantSpec& p : P.specs) roles.push_back(p.role);
  engine::CouplingOptions coupling = o.coupling;
  if (coupling.iteration_budget == 0)
    coupling.iteration_budget = engine::kIterationsPerStep * steps_to(scene, o.macro_step);
  // One rate: the schedule of the case; two: the multirate executor.
  if (P.rates.multirate()) coupling.iteration_budget /= P.rates.ratio;
  const std::unique_ptr<engine::CoupledSteps> coupled =
      engine::make_coupled_steps(P.rates, spec.scheme, o.feedthrough, coupling, P.ps, P.routing,
                                 roles, o.macro_step, P.statics.inputs);
  const auto* single = dynamic_cast<const engine::StepExecutor*>(coupled.get());
  auto record_row = [&](long n, const std::vector<StepResult>& m) {
    HistoryRow row = history.row(static_cast<double>(n) * o.macro_step, m, P.ps);
    r.history.push_back(row);
    record_coupling(r, P.specs, m);  // coupling_history.hpp: judged with the history
    if (o.on_row) o.on_row(row);
  };
  const std::vector<StepResult> initial = coupled->initialize(P.statics.inputs);
  record_row(0, initial);
  double static_max = 0;
  for (const StepResult& x : initial) static_max = std::max(static_max, x.max_abs_displacement);
  const double bound = verdict::divergence_bound(scene, static_max);
  const long N = steps_to(scene, o.macro_step);
  const std::unique_ptr<DirectExchange> direct =
      start_data_plane(r, o, transport, P, single ? &single->plan() : nullptr, bound, N);
  // The same plan either way: run by the master (in process or relayed), or
  // by the nodes over their peer links.
  MacroSteps* steps = coupled.get();
  if (direct) steps = direct.get();
  r.macro_steps = step_through(r, *steps, scene, o, N, bound, record_row, initial);
  if (direct) direct->drain();
  if (o.coupling.method == CouplingMethod::kImplicit) record_convergence(r, coupled->log(), o);
  complete_record(r, scene, P);
  r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace railcosim::run
