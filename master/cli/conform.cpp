#include "cli/conform.hpp"

#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <stdexcept>

#include "auth.hpp"
#include "cli/conform_fresh.hpp"
#include "cli/conform_peer.hpp"
#include "cli/conform_runs.hpp"
#include "cli/conform_statics.hpp"
#include "cosim_case.hpp"
#include "model.hpp"
#include "remote/remote_participant.hpp"
#include "scene.hpp"

namespace railcosim::cli {
namespace {

using Verdict = ConformItem::Verdict;
// A check's answer that starts so is a skip, not a failure.
constexpr const char* kSkipped = "skipped: ";
using Clock = std::chrono::steady_clock;

// What the checks share: the scene, the participant's configuration, where
// it serves.
struct Subject {
  const ConformOptions& o;
  Scene scene;
  SubsystemConfig config;
};

// Inputs that move the participant: per received quantity and point a value
// of the size a track sees (0.1 mm, 1 mm/s, 10 kN), varied along the points
// and over the steps.
CouplingData inputs_for(const Subject& s, long n) {
  CouplingData in;
  for (const InterfaceSpec& i : s.config.participant.interfaces) {
    InterfaceData d;
    const auto points = static_cast<std::size_t>(interface_points(s.scene, i));
    for (Quantity q : i.receives()) {
      std::vector<double> v(points);
      for (std::size_t k = 0; k < points; ++k) {
        const double shape = 1.0 + 0.1 * std::sin(0.7 * static_cast<double>(k) + 0.3 * n);
        v[k] = shape * (q == Quantity::kDisplacement ? 1e-4
                        : q == Quantity::kVelocity   ? 1e-3
                                                     : 1e4);
      }
      (q == Quantity::kDisplacement ? d.displacement
       : q == Quantity::kVelocity   ? d.velocity
                                    : d.force) = v;
    }
    in.push_back(d);
  }
  return in;
}

// A connection that has said hello as `participant` (and passed the
// challenge when the subject has a secret); returns the reply to the hello
// (or to the auth) in `reply`.
std::unique_ptr<Connection> open(const Subject& s, const std::string& participant,
                                 wire::Envelope& reply, std::uint32_t version = kProtocolVersion) {
  auto c = Connection::connect(s.o.address, std::chrono::milliseconds(5000));
  c->send(hello_envelope(participant, scene_fingerprint(s.scene), version));
  reply = c->receive(s.o.reply);
  if (reply.has_challenge() && s.o.token) {
    wire::Envelope auth;
    auth.mutable_auth()->set_mac(auth_answer(*s.o.token, participant, reply.challenge().nonce()));
    c->send(auth);
    reply = c->receive(s.o.reply);
  }
  return c;
}

// "" when `reply` is the error `code`, else what it is instead.
std::string is_error(const wire::Envelope& reply, wire::Error::Code code) {
  if (reply.has_error() && reply.error().code() == code) return "";
  if (reply.has_error())
    return "answered " + wire::Error::Code_Name(reply.error().code()) + ": " +
           reply.error().message();
  return "answered " + body_name(reply) + " instead of " + wire::Error::Code_Name(code);
}

// A configured and initialized session on a raw connection, for the checks
// that must break the protocol (each ends its session).
std::unique_ptr<Connection> initialized(const Subject& s) {
  wire::Envelope reply;
  auto c = open(s, s.config.participant.role, reply);
  if (!reply.has_hello_reply()) throw std::runtime_error("hello: " + body_name(reply));
  c->send(configure_envelope(s.scene, s.config));
  if (!c->receive(s.o.reply).has_configured()) throw std::runtime_error("configure refused");
  wire::Envelope init;
  *init.mutable_initialize()->mutable_inputs() = to_wire(inputs_for(s, 0));
  c->send(init);
  if (!c->receive(s.o.reply).has_step_report()) throw std::runtime_error("initialize refused");
  return c;
}

// SetInputs for step 0 with `inputs`; "" when answered BAD_REQUEST.
std::string refuses(const Subject& s, const CouplingData& inputs) {
  auto c = initialized(s);
  wire::Envelope e;
  e.mutable_set_inputs()->set_step(0);
  *e.mutable_set_inputs()->mutable_inputs() = to_wire(inputs);
  c->send(e);
  return is_error(c->receive(s.o.reply), wire::Error::BAD_REQUEST);
}

// The subject of the checks: the scene, and the role's participant in the
// case with the scene's step options.
Subject subject_of(const ConformOptions& options) {
  Subject s{options, load_scene(options.scene_path), {}};
  const std::vector<ParticipantSpec> parts = partition(s.scene, parse_case(options.case_name));
  for (const ParticipantSpec& p : parts)
    if (p.role == options.role) s.config.participant = p;
  if (s.config.participant.role.empty())
    throw std::runtime_error("case " + options.case_name + " has no " + options.role +
                             " participant");
  s.config.macro_step = s.scene.macro_step;
  s.config.tolerance = s.scene.tolerance;
  s.config.micro_steps = s.scene.micro_steps;
  s.config.carry_acceleration = s.scene.restart == "carry";
  return s;
}

// The items run so far, and the subject they are run on.
struct Checks {
  const Subject& s;
  std::vector<ConformItem> items;

  // Runs one item: `check` returns "" when it holds, else why not; an
  // exception is a failure with its message.
  bool item(const char* section, const char* what, const std::function<std::string()>& check) {
    ConformItem i{section, what, Verdict::kPass, ""};
    std::fprintf(stderr, "conform: %s %s\n", section, what);  // progress, before the item runs
    try {
      i.detail = check();
      if (i.detail.rfind(kSkipped, 0) == 0) {
        i.verdict = Verdict::kSkipped;
        i.detail.erase(0, std::string(kSkipped).size());
      } else if (!i.detail.empty()) {
        i.verdict = Verdict::kFail;
      }
    } catch (const std::exception& e) {
      i.verdict = Verdict::kFail;
      i.detail = e.what();
    }
    items.push_back(i);
    return i.verdict == Verdict::kPass;
  }
  void skip(const char* section, const char* what, const std::string& why) {
    items.push_back({section, what, Verdict::kSkipped, why});
  }
};

// §4: the hello and the challenge refuse what they must.
void check_hello(Checks& checks) {
  const Subject& s = checks.s;
  const std::string& role = s.config.participant.role;
  checks.item("§4", "hello: another protocol version is refused (VERSION_MISMATCH)", [&] {
    wire::Envelope reply;
    auto c = open(s, role, reply, kProtocolVersion + 1);
    return is_error(reply, wire::Error::VERSION_MISMATCH);
  });
  checks.item("§4", "hello: another participant is refused (WRONG_ROLE)", [&] {
    wire::Envelope reply;
    auto c = open(s, role == "vehicle" ? "soil" : "vehicle", reply);
    return is_error(reply, wire::Error::WRONG_ROLE);
  });
  if (s.o.token)
    checks.item(
        "§4", "with a secret, a hello for another participant gets the challenge first", [&] {
          auto c = Connection::connect(s.o.address, std::chrono::milliseconds(5000));
          c->send(
              hello_envelope(role == "vehicle" ? "soil" : "vehicle", scene_fingerprint(s.scene)));
          const wire::Envelope r = c->receive(s.o.reply);
          if (!r.has_challenge()) return "answered " + body_name(r) + " before the answer";
          // A wrong answer ends the session; its close frees the node
          // for the next check.
          wire::Envelope auth;
          auth.mutable_auth()->set_mac(std::string(32, 'x'));
          c->send(auth);
          c->receive(s.o.reply);
          try {
            c->receive(s.o.reply);
          } catch (const NetError&) {
          }
          return std::string();
        });
  if (s.o.token)
    checks.item("§4", "auth: a wrong answer to the challenge is refused (UNAUTHORIZED)", [&] {
      auto c = Connection::connect(s.o.address, std::chrono::milliseconds(5000));
      c->send(hello_envelope(role, scene_fingerprint(s.scene)));
      if (!c->receive(s.o.reply).has_challenge()) return std::string("no challenge");
      wire::Envelope auth;
      auth.mutable_auth()->set_mac(std::string(32, 'x'));
      c->send(auth);
      return is_error(c->receive(s.o.reply), wire::Error::UNAUTHORIZED);
    });
  else
    checks.skip("§4", "auth: a wrong answer to the challenge is refused", "no --token-file given");
}

// §5, §2, §7, §8: a session configured, held against a second master,
// through its statics and initialized; none when the configure failed.
std::unique_ptr<remote::RemoteParticipant> start_session(Checks& checks) {
  const Subject& s = checks.s;
  std::unique_ptr<remote::RemoteParticipant> p;
  remote::RemoteTimeouts t;
  t.reply = t.step_min = t.step_max = std::chrono::milliseconds(10000);
  const bool configured = checks.item("§5", "hello and configure accepted, outputs declared", [&] {
    p = std::make_unique<remote::RemoteParticipant>(s.o.address, s.scene, s.config, t, s.o.token);
    return std::string();
  });
  if (!configured) return nullptr;
  checks.item("§2", "a second master during the session is answered BUSY", [&] {
    wire::Envelope reply;
    auto c = open(s, s.config.participant.role, reply);
    return is_error(reply, wire::Error::BUSY);
  });
  checks.item("§7", "statics: outputs for held inputs, of the declared shape", [&] {
    p->statics(inputs_for(s, 0));
    return std::string();
  });
  checks.item("§8", "initialize: the state at step 0", [&] {
    p->initialize(inputs_for(s, 0));
    return std::string();
  });
  return p;
}

// §9, §10, §14, §11: relayed macro steps, a save and restore, the reply
// deadline, the results; ends the session.
void check_steps(Checks& checks, std::unique_ptr<remote::RemoteParticipant>& p) {
  const Subject& s = checks.s;
  Clock::duration slowest{};
  const long steps = s.o.steps;
  checks.item("§9", "macro steps, relayed: every report finite and of the declared shape", [&] {
    for (long n = 0; n < steps; ++n) {
      const auto t0 = Clock::now();
      p->set_inputs(n, inputs_for(s, n));
      const StepResult r = p->step(n);
      slowest = std::max(slowest, Clock::now() - t0);
      if (!r.finite) return "step " + std::to_string(n) + " reported non-finite values";
    }
    return std::string();
  });
  checks.item("§10", "save and restore: the steps after a restore repeat bit for bit", [&] {
    const ParticipantState saved = p->save();
    std::vector<StepResult> first, again;
    for (long n = steps; n < steps + 3; ++n) {
      p->set_inputs(n, inputs_for(s, n));
      first.push_back(p->step(n));
    }
    p->restore(saved);
    for (long n = steps; n < steps + 3; ++n) {
      p->set_inputs(n, inputs_for(s, n));
      again.push_back(p->step(n));
    }
    for (std::size_t k = 0; k < first.size(); ++k)
      if (first[k].outputs != again[k].outputs || first[k].history != again[k].history)
        return "step " + std::to_string(steps + static_cast<long>(k)) +
               " differs after the restore";
    return std::string();
  });
  checks.item("§14", "every step answered within the reply deadline", [&] {
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(slowest);
    return ms <= s.o.reply ? std::string()
                           : "the slowest step took " + std::to_string(ms.count()) +
                                 " ms (--reply-ms " + std::to_string(s.o.reply.count()) + ")";
  });
  checks.item("§11", "results of the declared fields, then shutdown", [&] {
    const ParticipantResults r = p->results();
    const std::size_t declared = p->channels().results.size();
    p.reset();  // sends Shutdown and waits for its Ack
    return r.fields.size() == declared ? std::string()
                                       : std::to_string(r.fields.size()) + " result fields, " +
                                             std::to_string(declared) + " declared";
  });
}

// §7, §10: inputs never sent before (conform_fresh.hpp).
void check_fresh(Checks& checks) {
  const Subject& s = checks.s;
  std::uint64_t seed = s.o.seed;
  while (seed == 0) seed = (std::uint64_t{std::random_device{}()} << 32) | std::random_device{}();
  const FreshSubject f{s.scene, s.config, s.o, [&s](long n) { return inputs_for(s, n); }, seed};
  checks.item("§7",
              "statics under loads never sent before: outputs change with the load, in "
              "proportion to first order",
              [&] { return check_static_loads(f); });
  checks.item("§10",
              "a restore followed by new inputs: outputs change in proportion, and "
              "equal a fresh session's with those inputs",
              [&] { return check_restore_new_inputs(f); });
  checks.item("§16",
              "statics direction: at the coupled static state the soil sinks and its springs "
              "carry the vehicle's weight, k_f sum(s_i) = m g",
              [&] { return check_soil_statics(s.scene, s.o); });
}

// §13, §17: inputs and peer links a participant must refuse.
void check_refusals(Checks& checks) {
  const Subject& s = checks.s;
  const auto spoiled = [&s](auto spoil) {  // every input of step 0, spoiled
    CouplingData bad = inputs_for(s, 0);
    for (InterfaceData& d : bad)
      for (auto* v : {&d.displacement, &d.velocity, &d.force})
        if (!v->empty()) spoil(*v);
    return refuses(s, bad);
  };
  checks.item("§13", "a non-finite input is refused (BAD_REQUEST)",
              [&] { return spoiled([](auto& v) { v[0] = std::nan(""); }); });
  checks.item("§13", "an input of the wrong length is refused (BAD_REQUEST)",
              [&] { return spoiled([](auto& v) { v.pop_back(); }); });
  checks.item("§17", "peer links: a wrong session key and an unexpected peer are refused", [&] {
    auto c = initialized(s);
    return check_peer_refusals(*c, s.config, s.o);
  });
}

// §17: the whole case on both data planes, bit for bit (conform_runs.hpp);
// skipped once an earlier item failed: the runs would only meet its fault
// again, with full judgement, for as long as the case lasts.
void check_planes(Checks& checks) {
  const char* what = "a whole run on the direct data plane equals the relayed run bit for bit";
  for (const ConformItem& i : checks.items)
    if (i.verdict == Verdict::kFail) {
      checks.skip("§17", what, "an earlier item failed (" + i.section + " " + i.what + ")");
      return;
    }
  checks.item("§17", what,
              [&] { return check_whole_runs(checks.s.o, checks.s.config.participant.role); });
}

}  // namespace

std::string conform_case(const std::string& role, const std::string& soil_model) {
  const RoleKind* r = find_role(role);
  if (r == nullptr) throw std::invalid_argument("no participant is called '" + role + "'");
  CaseSpec c = parse_case(r->conform_case);
  // A soil the master starts may take the ballast force only: its cut is X-T.
  if (const OutsideSoil* soil = find_outside_soil(soil_model); soil != nullptr && soil->force_only)
    for (CutChoice& cut : c.cuts)
      if (cut_kinds()[static_cast<std::size_t>(cut.cut)].lower == Component::kSoil)
        cut.coupling = Coupling::kXT;
  return c.name();
}

std::vector<ConformItem> run_conformance(const ConformOptions& options) {
  const Subject s = subject_of(options);
  Checks checks{s, {}};
  check_hello(checks);
  std::unique_ptr<remote::RemoteParticipant> p = start_session(checks);
  if (!p) return checks.items;
  check_steps(checks, p);
  check_fresh(checks);
  check_refusals(checks);
  check_planes(checks);
  return checks.items;
}

}  // namespace railcosim::cli
