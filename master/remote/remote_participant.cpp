#include "remote/remote_participant.hpp"

#include <algorithm>
#include <sstream>
#include <thread>

#include "auth.hpp"
#include "log.hpp"
#include "remote/peer_text.hpp"
#include "wire.hpp"

namespace railcosim::remote {

namespace {
std::string node_label(const SubsystemConfig& c) {
  return c.participant.role + " node";
}
}  // namespace

RemoteParticipant::RemoteParticipant(const Address& address, const Scene& scene,
                                     const SubsystemConfig& config, RemoteTimeouts timeouts,
                                     std::optional<std::string> token)
    : open_([address](std::chrono::milliseconds timeout) -> std::unique_ptr<FramedChannel> {
        return Connection::connect(address, timeout);
      }),
      peer_(address.str()),
      address_(address),
      config_(config),
      timeouts_(timeouts),
      shape_(reply_shape(scene, config)) {
  start(scene, token);
}

RemoteParticipant::RemoteParticipant(ChannelOpener open, std::string peer, const Scene& scene,
                                     const SubsystemConfig& config, RemoteTimeouts timeouts,
                                     std::optional<std::string> token)
    : open_(std::move(open)),
      peer_(std::move(peer)),
      config_(config),
      timeouts_(timeouts),
      shape_(reply_shape(scene, config)) {
  start(scene, token);
}

void RemoteParticipant::start(const Scene& scene, const std::optional<std::string>& token) {
  // With a secret, the hello carries this master's challenge too (mutual).
  const std::string mine = token ? random_nonce() : std::string();
  wire::Envelope reply = open_session(scene, mine);
  std::string challenge;
  if (reply.has_error())
    fail("hello failed: " + wire::Error::Code_Name(reply.error().code()) + ": " +
         terminal_text(reply.error().message()));
  if (reply.has_challenge()) {
    if (!token) fail("the node requires a shared secret: pass the same --token-file as the node's");
    challenge = reply.challenge().nonce();
    wire::Envelope auth;
    auth.mutable_auth()->set_mac(auth_answer(*token, config_.participant.role, challenge));
    send(auth, false);
    reply = await(wire::Envelope::kHelloReply, "auth");
  } else if (!reply.has_hello_reply()) {
    fail("unexpected " + body_name(reply) + " in reply to hello");
  }
  if (token) {
    const std::string why = proof_failure(*token, config_.participant.role, mine, challenge,
                                          reply.hello_reply().proof());
    if (!why.empty()) fail(why);
  }
  for (const auto& c : reply.hello_reply().capabilities()) {
    direct_ = direct_ || c == "direct";
    lockstep_capable_ = lockstep_capable_ || c == "lockstep";
  }

  wire::Envelope configure = configure_envelope(scene, config_);
  configure.mutable_configure()->set_progress_ms(
      static_cast<std::uint32_t>(timeouts_.progress.count()));
  send(configure, false);
  const wire::Configured declared = await(wire::Envelope::kConfigured, "configure").configured();
  channels_.history.assign(declared.history().begin(), declared.history().end());
  channels_.results.assign(declared.results().begin(), declared.results().end());
  check(declare_channels(shape_, channels_));
}

wire::Envelope RemoteParticipant::open_session(const Scene& scene, const std::string& nonce) {
  using Clock = std::chrono::steady_clock;
  const auto give_up = Clock::now() + timeouts_.busy;
  auto pause = std::chrono::milliseconds(50);
  while (true) {
    try {
      conn_ = open_(timeouts_.connect);
    } catch (const NetError& e) {
      throw NodeFailure(node_label(config_) + ": " + e.what());
    }
    wire::Envelope hello = hello_envelope(config_.participant.role, scene_fingerprint(scene));
    hello.mutable_hello()->set_nonce(nonce);
    send(hello, false);
    wire::Envelope reply;
    try {
      reply = conn_->receive(timeouts_.reply);
    } catch (const NetError& e) {
      fail(std::string("hello: ") + e.what());
    }
    in_flight_.clear();
    if (!reply.has_error() || reply.error().code() != wire::Error::BUSY) return reply;
    conn_->close();
    const auto now = Clock::now();
    if (now >= give_up)
      fail("hello failed: BUSY: " + terminal_text(reply.error().message()) + " (asked again for " +
           std::to_string(timeouts_.busy.count()) + " ms)");
    // Sleep in slices, so that a stop signal is seen within one.
    const auto nap = std::min(pause, std::chrono::ceil<std::chrono::milliseconds>(give_up - now));
    for (auto slept = std::chrono::milliseconds(0); slept < nap; slept += kInterruptPoll) {
      if (const int sig = interrupt_signal())
        fail("interrupted by signal " + std::to_string(sig) + " while the node was busy");
      std::this_thread::sleep_for(std::min(kInterruptPoll, nap - slept));
    }
    pause = std::min(pause * 2, std::chrono::milliseconds(500));
  }
}

RemoteParticipant::~RemoteParticipant() {
  if (!conn_) return;
  try {
    // Wait (briefly) for the node to end the session, so that the next
    // session can start on it at once; acks still in flight come first.
    wire::Envelope bye;
    bye.mutable_shutdown();
    send(bye, true);
    await(wire::Envelope::kAck, "shutdown", std::chrono::milliseconds(2000));
  } catch (const std::exception&) {
    // The node is gone already: nothing to end.
  }
  conn_->close();
}

std::string RemoteParticipant::name() const {
  return node_label(config_) + " at " + peer_;
}

void RemoteParticipant::fail(const std::string& what) const {
  throw NodeFailure(failure_text(step_, what));
}

std::string RemoteParticipant::failure_text(long step, const std::string& what) const {
  std::ostringstream s;
  // Whatever a node's words it holds, they stay on this line.
  s << name() << ": " << terminal_text(what);
  // Before the first step there is no macro step to name (the protocol's -1).
  if (!stepping_ || step < 0)
    s << " before the run";
  else
    s << " at macro step " << step << " (t = " << static_cast<double>(step) * config_.macro_step
      << " s)";
  return s.str();
}

void RemoteParticipant::send(wire::Envelope request, bool expects_ack) {
  request.set_id(next_id_++);
  try {
    conn_->send(request, timeouts_.reply);
  } catch (const NetError& e) {
    fail(e.what());
  } catch (const ProtocolError& e) {
    fail(e.what());
  }
  if (expects_ack) ++pending_acks_;
  in_flight_.push_back(request.id());
}

wire::Envelope RemoteParticipant::await(wire::Envelope::BodyCase expected, const char* what,
                                        std::chrono::milliseconds timeout, StepWatch* watch) {
  using Clock = std::chrono::steady_clock;
  while (true) {
    wire::Envelope reply;
    try {
      reply = conn_->receive(watch ? watch->left(Clock::now()) : timeout);
    } catch (const NetError& e) {
      conn_->close();  // half a frame may be in it: no use waiting for a goodbye
      if (watch && e.kind() == NetError::Kind::kTimeout) fail(watch->why(Clock::now()));
      fail(e.what());
    }
    if (watch && reply.has_progress()) {
      // Progress of the request sent last (a step), acks of pipelined
      // requests may still be due.
      if (in_flight_.empty() || reply.id() != in_flight_.back())
        fail("bad reply: a progress frame with id " + std::to_string(reply.id()) +
             " while the step's request has id " +
             std::to_string(in_flight_.empty() ? 0 : in_flight_.back()));
      check(watch->take(reply.progress(), step_, Clock::now()));
      continue;
    }
    if (!reply.has_error())
      check(check_reply_id(reply.id(), in_flight_.empty() ? 0 : in_flight_.front()));
    if (!in_flight_.empty()) in_flight_.pop_front();
    if (reply.has_error() && reply.error().code() == wire::Error::STEP_FAILED) {
      std::ostringstream s;
      s << name() << ": " << terminal_text(reply.error().message()) << " at macro step " << step_;
      throw StepFailure(s.str());
    }
    if (reply.has_error()) {
      const auto& err = reply.error();
      fail(std::string(what) + " failed: " + wire::Error::Code_Name(err.code()) + ": " +
           terminal_text(err.message()));
    }
    if (reply.body_case() == wire::Envelope::kAck && pending_acks_ > 0) {
      --pending_acks_;
      if (expected == wire::Envelope::kAck && pending_acks_ == 0) return reply;
      if (expected != wire::Envelope::kAck) continue;
    }
    if (reply.body_case() != expected)
      fail(std::string("unexpected ") + body_name(reply) + " in reply to " + what);
    return reply;
  }
}

CouplingData RemoteParticipant::statics(const CouplingData& inputs) {
  wire::Envelope e;
  *e.mutable_statics()->mutable_inputs() = to_wire(inputs);
  flush_inputs();
  send(std::move(e), false);
  // A static solve may take longer than the reply limit while it shows
  // progress (frames with step -1), within the statics budget.
  const auto start = std::chrono::steady_clock::now();
  StepWatch watch(timeouts_.reply, timeouts_.statics_budget(), start, true);
  CouplingData out = from_wire(
      await(wire::Envelope::kOutputs, "statics", timeouts_.reply, &watch).outputs().data());
  check(check_outputs(out, shape_));
  const auto end = std::chrono::steady_clock::now();
  using Seconds = std::chrono::duration<double>;
  if (watch.counted() > 0)
    logger("master")->debug(
        "{}: static state in {:.1f} s, {} progress frame(s) counted, the longest quiet {:.1f} s",
        name(), Seconds(end - start).count(), watch.counted(),
        Seconds(watch.longest_quiet(end)).count());
  return out;
}

StepResult RemoteParticipant::initialize(const CouplingData& inputs) {
  wire::Envelope e;
  *e.mutable_initialize()->mutable_inputs() = to_wire(inputs);
  send(e, false);
  const wire::StepReport w = await(wire::Envelope::kStepReport, "initialize").step_report();
  StepResult r = from_wire(w);
  check(check_step_report(r, w.step(), w.t(), 0, shape_));
  return r;
}

void RemoteParticipant::set_inputs(long n, const CouplingData& inputs) {
  step_ = n;
  stepping_ = true;
  pending_inputs_ = inputs;  // sent with the step, or flushed before any other request
  pending_end_.reset();
  pending_waves_.reset();
}

void RemoteParticipant::set_inputs(long n, const CouplingData& start, const CouplingData& end) {
  step_ = n;
  stepping_ = true;
  pending_inputs_ = start;
  pending_end_ = end;
  pending_waves_.reset();
}

template <class Message>
bool RemoteParticipant::take_pending(Message* m) {
  if (pending_waves_) *m->mutable_waveforms() = to_wire(*pending_waves_);
  if (pending_inputs_) *m->mutable_inputs() = to_wire(*pending_inputs_);
  if (pending_end_) *m->mutable_inputs_end() = to_wire(*pending_end_);
  const bool any = pending_inputs_ || pending_waves_;
  pending_inputs_.reset();
  pending_end_.reset();
  pending_waves_.reset();
  return any;
}

void RemoteParticipant::flush_inputs() {
  // A kept checkpoint's save or restore goes first, as it was asked for.
  if (pending_keep_) {
    wire::Envelope e;
    e.mutable_save()->set_keep(true);
    pending_keep_ = false;
    send(e, true);
  }
  if (pending_restore_) {
    wire::Envelope e;
    e.mutable_restore()->set_kept(true);
    pending_restore_ = false;
    send(e, true);
  }
  wire::Envelope e;
  auto* s = e.mutable_set_inputs();
  s->set_step(step_);
  s->set_t(static_cast<double>(step_) * config_.macro_step);
  if (take_pending(s)) send(e, true);  // pipelined: its ack is read with the next reply
}

CouplingData RemoteParticipant::outputs() {
  wire::Envelope e;
  e.mutable_get_outputs()->set_step(step_);
  CouplingData out = from_wire(request(std::move(e), wire::Envelope::kOutputs).outputs().data());
  check(check_outputs(out, shape_));
  return out;
}

void RemoteParticipant::start_step(long n) {
  step_ = n;
  wire::Envelope e;
  auto* s = e.mutable_step();
  s->set_step(n);
  s->set_t(static_cast<double>(n) * config_.macro_step);
  s->set_h(config_.macro_step);
  s->set_keep_checkpoint(pending_keep_);
  s->set_restore_checkpoint(pending_restore_);
  pending_keep_ = pending_restore_ = false;
  step_started_ = std::chrono::steady_clock::now();
  take_pending(s);
  send(e, false);
}

wire::Envelope RemoteParticipant::request(wire::Envelope e, wire::Envelope::BodyCase expected) {
  flush_inputs();
  const std::string what = body_name(e);
  send(std::move(e), false);
  return await(expected, what.c_str());
}

ParticipantResults RemoteParticipant::results() {
  wire::Envelope e;
  e.mutable_get_results();
  const wire::Results w = request(std::move(e), wire::Envelope::kResults).results();
  ParticipantResults r;
  for (const auto& f : w.fields()) r.fields.emplace_back(f.values().begin(), f.values().end());
  r.micro_steps = w.micro_steps();
  check(check_results(r, shape_));
  return r;
}

ParticipantState RemoteParticipant::save() {
  if (lockstep_) {
    flush_inputs();  // inputs held before the save belong to the snapshot
    pending_keep_ = true;
    return ParticipantState{{}, true};
  }
  wire::Envelope e;
  e.mutable_save();
  const wire::State w = request(std::move(e), wire::Envelope::kState).state();
  ParticipantState st{{w.values().begin(), w.values().end()}};
  check(check_state(st));
  return st;
}

void RemoteParticipant::restore(const ParticipantState& state) {
  pending_inputs_.reset();  // the restored state brings its own held inputs
  pending_end_.reset();
  pending_waves_.reset();
  if (state.kept) {
    if (!lockstep_) throw std::logic_error(name() + ": a kept checkpoint outside a lock step");
    // Not saved yet (the save rides with the next step): the state is still
    // the snapshot's.
    if (!pending_keep_) pending_restore_ = true;
    return;
  }
  wire::Envelope e;
  auto* r = e.mutable_restore()->mutable_state();
  for (double v : state.values) r->add_values(v);
  send(e, true);
  await(wire::Envelope::kAck, "restore");
}

void RemoteParticipant::fail_at(long step, const std::string& what) {
  step_ = step;
  fail(what);
}

}  // namespace railcosim::remote
