#include "cli/conform.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>

#include <unistd.h>

#include "auth.hpp"
#include "cli/conform_peer.hpp"
#include "cosim_case.hpp"
#include "model.hpp"
#include "remote/remote_participant.hpp"
#include "scene.hpp"

namespace railcosim {
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

std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The whole case run by this program with the subject as ROLE, on `plane`;
// returns the run folder.
std::filesystem::path whole_run(const Subject& s, const std::string& plane,
                                const std::filesystem::path& out, const std::string& token_file) {
  std::string cmd = quoted(s.o.master_program) + " run --scene " + quoted(s.o.scene_path) +
                    " --case " + quoted(s.o.case_name) + " --node " +
                    quoted(s.config.participant.role + "=" + s.o.address.str()) + " --data-plane " +
                    plane + " --out " + quoted((out / plane).string());
  if (!token_file.empty()) cmd += " --token-file " + quoted(token_file);
  cmd += " >" + quoted((out / (plane + ".log")).string()) + " 2>&1";
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("the " + plane + " run failed: " + read_all(out / (plane + ".log")));
  return out / plane / s.o.case_name;
}

}  // namespace

std::string conform_case(const std::string& role, const std::string& soil_model) {
  if (role == "soil") return soil_model == "fe" ? "ss-xt-jacobi" : "ss-xx-jacobi";
  if (role == "rail") return "wr-xx+rs-xx-jacobi";
  return "wr-xx-jacobi";
}

std::vector<ConformItem> run_conformance(const ConformOptions& options) {
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

  std::vector<ConformItem> items;
  // Runs one item: `check` returns "" when it holds, else why not; an
  // exception is a failure with its message.
  auto item = [&](const char* section, const char* what,
                  const std::function<std::string()>& check) {
    ConformItem i{section, what, Verdict::kPass, ""};
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
  };
  auto skip = [&](const char* section, const char* what, const std::string& why) {
    items.push_back({section, what, Verdict::kSkipped, why});
  };
  const std::string& role = s.config.participant.role;

  item("§4", "hello: another protocol version is refused (VERSION_MISMATCH)", [&] {
    wire::Envelope reply;
    auto c = open(s, role, reply, kProtocolVersion + 1);
    return is_error(reply, wire::Error::VERSION_MISMATCH);
  });
  item("§4", "hello: another participant is refused (WRONG_ROLE)", [&] {
    wire::Envelope reply;
    auto c = open(s, role == "vehicle" ? "soil" : "vehicle", reply);
    return is_error(reply, wire::Error::WRONG_ROLE);
  });
  if (options.token)
    item("§4", "auth: a wrong answer to the challenge is refused (UNAUTHORIZED)", [&] {
      auto c = Connection::connect(options.address, std::chrono::milliseconds(5000));
      c->send(hello_envelope(role, scene_fingerprint(s.scene)));
      if (!c->receive(options.reply).has_challenge()) return std::string("no challenge");
      wire::Envelope auth;
      auth.mutable_auth()->set_mac(std::string(32, 'x'));
      c->send(auth);
      return is_error(c->receive(options.reply), wire::Error::UNAUTHORIZED);
    });
  else
    skip("§4", "auth: a wrong answer to the challenge is refused", "no --token-file given");

  std::unique_ptr<RemoteParticipant> p;
  RemoteTimeouts t;
  t.reply = t.step_min = t.step_max = std::chrono::milliseconds(10000);
  const bool configured = item("§5", "hello and configure accepted, outputs declared", [&] {
    p = std::make_unique<RemoteParticipant>(options.address, s.scene, s.config, t, options.token);
    return std::string();
  });
  if (!configured) return items;
  item("§2", "a second master during the session is answered BUSY", [&] {
    wire::Envelope reply;
    auto c = open(s, role, reply);
    return is_error(reply, wire::Error::BUSY);
  });
  item("§7", "statics: outputs for held inputs, of the declared shape", [&] {
    p->statics(inputs_for(s, 0));
    return std::string();
  });
  item("§8", "initialize: the state at step 0", [&] {
    p->initialize(inputs_for(s, 0));
    return std::string();
  });
  Clock::duration slowest{};
  const long steps = options.steps;
  item("§9", "macro steps, relayed: every report finite and of the declared shape", [&] {
    for (long n = 0; n < steps; ++n) {
      const auto t0 = Clock::now();
      p->set_inputs(n, inputs_for(s, n));
      const StepResult r = p->step(n);
      slowest = std::max(slowest, Clock::now() - t0);
      if (!r.finite) return "step " + std::to_string(n) + " reported non-finite values";
    }
    return std::string();
  });
  item("§10", "save and restore: the steps after a restore repeat bit for bit", [&] {
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
  item("§14", "every step answered within the reply deadline", [&] {
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(slowest);
    return ms <= options.reply
               ? std::string()
               : "the slowest step took " + std::to_string(ms.count()) + " ms (--reply-ms " +
                     std::to_string(options.reply.count()) + ")";
  });
  item("§11", "results of the declared fields, then shutdown", [&] {
    const ParticipantResults r = p->results();
    const std::size_t declared = p->channels().results.size();
    p.reset();  // sends Shutdown and waits for its Ack
    return r.fields.size() == declared ? std::string()
                                       : std::to_string(r.fields.size()) + " result fields, " +
                                             std::to_string(declared) + " declared";
  });
  item("§13", "a non-finite input is refused (BAD_REQUEST)", [&] {
    CouplingData bad = inputs_for(s, 0);
    for (InterfaceData& d : bad)
      for (auto* v : {&d.displacement, &d.velocity, &d.force})
        if (!v->empty()) (*v)[0] = std::nan("");
    return refuses(s, bad);
  });
  item("§13", "an input of the wrong length is refused (BAD_REQUEST)", [&] {
    CouplingData bad = inputs_for(s, 0);
    for (InterfaceData& d : bad)
      for (auto* v : {&d.displacement, &d.velocity, &d.force})
        if (!v->empty()) v->pop_back();
    return refuses(s, bad);
  });
  item("§17", "peer links: a wrong session key and an unexpected peer are refused", [&] {
    auto c = initialized(s);
    return check_peer_refusals(*c, s.config, options);
  });
  item("§17", "a whole run on the direct data plane equals the relayed run bit for bit", [&] {
    const auto out = std::filesystem::temp_directory_path() /
                     ("railcosim-conform-" + std::to_string(::getpid()));
    std::filesystem::create_directories(out);
    const auto relay = whole_run(s, "relay", out, options.token_file);
    const auto direct = whole_run(s, "direct", out, options.token_file);
    std::string why;
    if (read_all(direct / "summary.json").find("\"data_plane\": \"direct\"") == std::string::npos)
      why = std::string(kSkipped) + "the participant does not offer the direct plane";
    else if (read_all(direct / "history.csv") != read_all(relay / "history.csv"))
      why = "history.csv differs between the planes";
    std::filesystem::remove_all(out);
    return why;
  });
  return items;
}

int report_conformance(const std::vector<ConformItem>& items, const ConformOptions& o) {
  int passed = 0, failed = 0, skipped = 0;
  std::printf("conformance of the %s participant at %s (%s, %s):\n", o.role.c_str(),
              o.address.str().c_str(), o.scene_path.c_str(), o.case_name.c_str());
  for (const ConformItem& i : items) {
    const char* v = i.verdict == Verdict::kPass   ? "PASS"
                    : i.verdict == Verdict::kFail ? "FAIL"
                                                  : "SKIP";
    (i.verdict == Verdict::kPass ? passed : i.verdict == Verdict::kFail ? failed : skipped)++;
    std::printf("  %s  %-4s %s%s%s\n", v, i.section.c_str(), i.what.c_str(),
                i.detail.empty() ? "" : ": ", i.detail.c_str());
  }
  std::printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
  return failed == 0 ? 0 : 1;
}

}  // namespace railcosim

namespace railcosim {

void add_conform_command(CLI::App& app, ConformArgs& a) {
  a.command = app.add_subcommand(
      "conform",
      "Check a participant that serves at HOST:PORT against the protocol's checklist "
      "(docs/protocol.md §18): one line per item, PASS/FAIL/SKIP, with the section it tests");
  a.command->add_option("--scene", a.scene_path, "Scene file the participant is checked with")
      ->required()
      ->check(CLI::ExistingFile);
  a.command
      ->add_option("--node", a.node,
                   "ROLE=HOST:PORT of the participant (vehicle, track, "
                   "rail, soil)")
      ->required();
  a.command->add_option("--case", a.case_name,
                        "Case it is checked in (default: ss-xx-jacobi for soil, ss-xt-jacobi for "
                        "the FE soil, "
                        "wr-xx+rs-xx-jacobi for rail, wr-xx-jacobi otherwise)");
  a.command->add_option("--token-file", a.token_file, "Its shared secret, if it has one")
      ->check(CLI::ExistingFile);
  a.command
      ->add_option("--reply-ms", a.reply_ms,
                   "The slowest reply a check allows, ms (a participant slower than this "
                   "per macro step fails the deadline item)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  a.command->add_option("--steps", a.steps, "Macro steps of the relayed check")
      ->check(CLI::Range(4, 100000))
      ->capture_default_str();
}

int do_conform(const ConformArgs& a) {
  ConformOptions o;
  o.scene_path = a.scene_path;
  const auto eq = a.node.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("--node " + a.node + ": expected ROLE=HOST:PORT");
  o.role = a.node.substr(0, eq);
  o.address = parse_address(a.node.substr(eq + 1), "--node " + o.role);
  o.case_name =
      a.case_name.empty() ? conform_case(o.role, load_scene(a.scene_path).soil_model) : a.case_name;
  if (!a.token_file.empty()) {
    o.token = read_token_file(a.token_file);
    o.token_file = a.token_file;
  }
  o.reply = std::chrono::milliseconds(a.reply_ms);
  o.steps = a.steps;
  std::error_code ec;
  o.master_program = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  return report_conformance(run_conformance(o), o);
}

}  // namespace railcosim
