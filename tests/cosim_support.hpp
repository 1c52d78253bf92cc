// Test helper: the in-process participants of a case at their coupled static
// state, found through the interfaces as the master finds it.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/coupled_statics.hpp"
#include "engine/schedule.hpp"
#include "remote/transport.hpp"
#include "run/assess.hpp"
#include "run/runner.hpp"
#include "subsystem.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim::test {

struct InprocCase {
  std::vector<ParticipantSpec> specs;
  std::vector<std::unique_ptr<Subsystem>> subs;
  std::vector<Participant*> ps;
  engine::StaticsOutcome statics;  // statics.inputs[p]: what participant p holds
};

// The configuration of participant `role` in a case; throws if the case has
// no such participant.
inline SubsystemConfig config_of(const Scene& scene, const std::string& case_name,
                                 const std::string& role) {
  SubsystemConfig cfg;
  for (const ParticipantSpec& p : partition(scene, parse_case(case_name)))
    if (p.role == role) cfg.participant = p;
  if (cfg.participant.role != role)
    throw std::logic_error(case_name + " has no " + role + " participant");
  cfg.macro_step = scene.macro_step;
  cfg.tolerance = scene.tolerance;
  return cfg;
}

inline InprocCase inproc_case_at_statics(const Scene& scene, const std::string& case_name) {
  InprocCase c;
  c.specs = partition(scene, parse_case(case_name));
  std::vector<CouplingData> zero;
  for (const ParticipantSpec& p : c.specs) {
    SubsystemConfig cfg;
    cfg.participant = p;
    cfg.macro_step = scene.macro_step;
    cfg.tolerance = scene.tolerance;
    c.subs.push_back(std::make_unique<Subsystem>(scene, cfg));
    c.ps.push_back(c.subs.back().get());
    zero.push_back(engine::zero_inputs(scene, p));
  }
  c.statics = engine::find_static_state(c.ps, engine::make_routing(c.specs), zero);
  return c;
}

// Case `name` at macro step H with coupling `c`, judged against the
// monolithic run at the same H and the scene's tolerance; in process unless
// a transport is given.
inline run::RunRecord judged(const Scene& scene, const std::string& name, double H,
                             const engine::CouplingOptions& c,
                             const remote::SceneTransport* transport = nullptr) {
  run::RunOptions o;
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  o.coupling = c;
  const run::RunRecord reference = run::run_monolithic(scene, o);
  const remote::SceneTransport inproc = remote::inproc_transport(scene);
  const remote::SceneTransport& t = transport ? *transport : inproc;
  run::RunRecord r = run::run_cosim(scene, parse_case(name), o, t.factory, t.name);
  run::assess(r, reference, scene, parse_case(name), o);
  return r;
}

}  // namespace railcosim::test
