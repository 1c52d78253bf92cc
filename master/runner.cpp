#include "runner.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "evaluation.hpp"
#include "log.hpp"
#include "monolithic.hpp"
#include "schedule.hpp"

namespace railcosim {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<double> rail_positions(const Scene& scene) {
  std::vector<double> x(static_cast<std::size_t>(scene.rail_nodes()));
  for (std::size_t k = 0; k < x.size(); ++k)
    x[k] = scene.rail_start + static_cast<double>(k) * scene.element_length();
  return x;
}

long steps_to(const Scene& scene, double H) {
  return std::lround(scene.end_time / H);
}

void check_stop(const RunOptions& o, long n) {
  if (o.stop && o.stop->load() != 0) {
    std::ostringstream s;
    s << "interrupted by signal " << o.stop->load() << " at macro step " << n
      << " (t = " << static_cast<double>(n) * o.macro_step << " s)";
    throw std::runtime_error(s.str());
  }
}

}  // namespace

ParticipantFactory inproc_factory(const Scene& scene) {
  return [scene](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    return std::make_unique<Subsystem>(scene, c);
  };
}

RunRecord failed_record(const Scene& scene, const CaseSpec& spec, const RunOptions& o,
                        const std::string& transport, const std::string& why) {
  RunRecord r;
  r.case_name = spec.name();
  if (!spec.monolithic) {
    r.split = to_string(spec.split);
    r.coupling = to_string(spec.coupling);
    r.scheme = to_string(spec.scheme);
    r.feedthrough = to_string(o.feedthrough);
    r.transport = transport;
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
  const long N = steps_to(scene, o.macro_step);
  r.history.reserve(static_cast<std::size_t>(N + 1));
  auto record_row = [&](const HistoryRow& row) {
    r.history.push_back(row);
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
  r.max_abs_error_m = 0.0;
  r.rel_l2_error = 0.0;
  r.history_error = 0.0;
  r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

RunRecord run_cosim(const Scene& scene, const CaseSpec& spec, const RunOptions& o,
                    const ParticipantFactory& make, const std::string& transport) {
  const auto t0 = Clock::now();
  auto log = logger("master");
  RunRecord r;
  r.case_name = spec.name();
  r.split = to_string(spec.split);
  r.coupling = to_string(spec.coupling);
  r.scheme = to_string(spec.scheme);
  r.feedthrough = to_string(o.feedthrough);
  r.macro_step = o.macro_step;
  r.t_end = scene.end_time;
  r.transport = transport;

  SubsystemConfig c1{spec.split, Side::kS1, spec.coupling, o.macro_step, o.tolerance};
  SubsystemConfig c2 = c1;
  c2.side = Side::kS2;
  auto s1 = make(c1);
  auto s2 = make(c2);
  auto schedule = make_schedule(spec.scheme, o.feedthrough, *s1, *s2);
  auto record_row = [&](const MacroStepResult& m) {
    if (!m.s1.row) throw std::runtime_error(s1->name() + " reported no wheel history row");
    r.history.push_back(*m.s1.row);
    if (o.on_row) o.on_row(*m.s1.row);
  };
  record_row(schedule->initialize());

  const double bound = divergence_bound(scene);
  const long N = steps_to(scene, o.macro_step);
  long n = 0;
  for (; n < N; ++n) {
    check_stop(o, n);
    MacroStepResult m;
    try {
      m = schedule->advance(n);
    } catch (const StepFailure& e) {
      // A subsystem whose micro steps run away: the co-simulation diverges.
      std::ostringstream s;
      s << "diverged at macro step " << n + 1
        << " (t = " << static_cast<double>(n + 1) * o.macro_step << " s): " << e.what();
      r.status = "diverged";
      r.message = s.str();
      log->warn("{}: {}", r.case_name, r.message);
      ++n;
      break;
    }
    record_row(m);
    if (o.on_progress) o.on_progress(n + 1, N);
    const bool finite = m.s1.finite && m.s2.finite;
    const double umax = std::max(m.s1.max_abs_displacement, m.s2.max_abs_displacement);
    if (!finite || umax > bound) {
      std::ostringstream s;
      s << "diverged at macro step " << n + 1
        << " (t = " << static_cast<double>(n + 1) * o.macro_step << " s): ";
      if (!finite)
        s << "a state value is not finite";
      else
        s << "|u| = " << umax << " m exceeds " << scene.divergence_factor
          << " x the largest static displacement (" << bound << " m)";
      r.status = "diverged";
      r.message = s.str();
      log->warn("{}: {}", r.case_name, r.message);
      ++n;
      break;
    }
  }
  r.macro_steps = n;
  ParticipantResults p1, p2;
  try {
    p1 = s1->results();
    p2 = s2->results();
  } catch (const std::exception& e) {
    // A node that gave up on a diverging step has ended its session.
    if (r.status != "diverged") throw;
    log->warn("{}: no final results after the divergence: {}", r.case_name, e.what());
  }
  r.micro_steps["s1"] = p1.micro_steps;
  r.micro_steps["s2"] = p2.micro_steps;
  r.x = rail_positions(scene);
  r.deflection = spec.split == Split::kWheelRail ? p2.rail_deflection : p1.rail_deflection;
  r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace railcosim
