#include "session.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "auth.hpp"
#include "channel_names.hpp"

namespace railcosim {
namespace {

std::string hex(std::uint64_t v) {
  std::ostringstream s;
  s << std::hex << v;
  return s.str();
}

}  // namespace

wire::Envelope NodeSession::hello_reply(std::uint64_t id) const {
  wire::Envelope reply;
  reply.set_id(id);
  auto* r = reply.mutable_hello_reply();
  r->set_protocol_version(kProtocolVersion);
  r->set_participant(participant_);
  r->set_name(options_.name);
  // The direct data plane needs a way to stream reports (the server's).
  if (report_) r->add_capabilities("direct");
  if (report_ && next_request_) r->add_capabilities("lockstep");
  return reply;
}

wire::Envelope NodeSession::links(const wire::Envelope& req) {
  if (step_ != 0 || runner_)
    throw ProtocolError(wire::Error::OUT_OF_ORDER,
                        "links are set once, after initialize and before the first step");
  links_ = links_from_wire(req.links(), outputs_.size(), participant_);
  bool accepts = false;
  for (const LinkPlan& l : links_->links) accepts = accepts || !l.connect;
  inbox_->set_waiting(accepts);
  wire::Envelope reply;
  reply.set_id(req.id());
  reply.mutable_ack();
  return reply;
}

wire::Envelope NodeSession::window(const wire::Envelope& req) {
  if (!runner_) {
    if (!links_) throw ProtocolError(wire::Error::OUT_OF_ORDER, "a window needs links first");
    if (!report_)
      throw ProtocolError(wire::Error::BAD_REQUEST, "this connection cannot stream reports");
    LinkIdentity me{participant_, options_.token, options_.name, max_frame_bytes_};
    // A Reports frame with no reports tells the master whom this node waits for.
    auto waiting = [this, id = req.id()](const std::string& peer) {
      wire::Envelope e;
      e.set_id(id);
      e.mutable_reports()->set_waiting_for(peer);
      report_(encode_frame(e));
    };
    runner_ = std::make_unique<WindowRunner>(
        *served_, *links_, open_links(*links_, me, *inbox_, master_gone_, waiting), macro_step_,
        outputs_, in_shape_, step_, max_frame_bytes_);
  }
  wire::Envelope reply;
  reply.set_id(req.id());
  try {
    *reply.mutable_window_done() = runner_->run(req.window(), req.id(), report_, master_gone_);
  } catch (...) {
    step_ = runner_->point();
    throw;
  }
  step_ = runner_->point();
  return reply;
}

void NodeSession::check_pinned_scene() const {
  if (!options_.pinned_scene) return;
  const std::uint64_t mine = scene_fingerprint(*options_.pinned_scene);
  if (fingerprint_ != mine)
    throw ProtocolError(wire::Error::SCENE_MISMATCH,
                        "the master's scene (fingerprint " + hex(fingerprint_) +
                            ") differs from this node's " + options_.pinned_scene->source +
                            " (fingerprint " + hex(mine) + ")");
}

void NodeSession::check_hello_target() const {
  if (options_.role != "any" && participant_ != options_.role)
    throw ProtocolError(wire::Error::WRONG_ROLE,
                        "this node serves the " + options_.role + " participant, not the " +
                            (participant_.empty() ? "unnamed" : participant_) + " participant");
  if (participant_.empty())
    throw ProtocolError(wire::Error::WRONG_ROLE, "the hello names no participant to serve");
  if (peer_hello_)
    throw ProtocolError(wire::Error::WRONG_ROLE,
                        "a peer link from the " + peer_of_ +
                            " participant reached a node that has no session expecting it");
}

wire::Envelope NodeSession::handle(const wire::Envelope& request, bool& close) {
  close = false;
  if (request.has_window() && request.window().lockstep() && state_ == State::kConfigured)
    return lockstep(request, close);
  wire::Error::Code code = wire::Error::INTERNAL;
  std::string message;
  std::string sender;
  try {
    return dispatch(request, close);
  } catch (const ProtocolError& e) {
    code = e.code();
    message = e.what();
  } catch (const CallOrderError& e) {
    code = wire::Error::OUT_OF_ORDER;
    message = e.what();
  } catch (const StepFailure& e) {
    code = wire::Error::STEP_FAILED;
    message = e.what();
  } catch (const BadRequestError& e) {
    // Inputs that do not fit, or a request the participant cannot serve (a
    // ramp for an FMU that takes held inputs only, a state it cannot save).
    code = wire::Error::BAD_REQUEST;
    message = e.what();
  } catch (const LinkError& e) {
    // Everything that goes wrong on a peer link is PEER_FAILED; a peer whose
    // data or frames this node refuses is named in `sender`, the root cause.
    code = wire::Error::PEER_FAILED;
    message = e.what();
    sender = e.sender();
  } catch (const std::exception& e) {
    message = std::string("internal error: ") + e.what();
  }
  // Any error ends the session.
  close = true;
  wire::Envelope reply = error_envelope(request.id(), code, message, step_,
                                        step_ < 0 ? 0.0 : static_cast<double>(step_) * macro_step_);
  reply.mutable_error()->set_sender(sender);
  return reply;
}

wire::Envelope NodeSession::dispatch(const wire::Envelope& req, bool& close) {
  using E = wire::Envelope;
  // Before a master has proved it knows the secret, nothing but the answer counts.
  if (req.body_case() == E::kShutdown && state_ != State::kAwaitAuth) {
    close = true;
    wire::Envelope reply;
    reply.set_id(req.id());
    reply.mutable_ack();
    return reply;
  }
  switch (state_) {
    case State::kAwaitHello:
      return on_hello(req);
    case State::kAwaitAuth:
      return on_auth(req);
    case State::kAwaitConfigure:
      return on_configure(req);
    case State::kConfigured:
      break;
  }
  const std::string what = body_name(req);
  switch (req.body_case()) {
    case E::kStatics: {
      // A participant's statics() that calls work_progress() shows progress
      // (step -1: before the run), as a step's integrator does.
      std::optional<ScopedWorkProgress> progress;
      watch_progress(progress, req.id(), [] { return -1L; });
      return on_statics(req);
    }
    case E::kInitialize:
      return on_initialize(req);
    case E::kSetInputs:
      return on_set_inputs(req);
    case E::kGetOutputs:
      return on_get_outputs(req);
    case E::kStep: {
      std::optional<ScopedWorkProgress> progress;
      watch_progress(progress, req.id(), [&req] { return static_cast<long>(req.step().step()); });
      return on_step(req);
    }
    case E::kGetResults:
      return on_get_results(req);
    case E::kSave:
      return on_save(req);
    case E::kRestore:
      return on_restore(req);
    case E::kRecordSamples:
      return record_samples(req);
    case E::kLinks:
      return links(req);
    case E::kWindow: {
      std::optional<ScopedWorkProgress> progress;
      watch_progress(progress, req.id(), [this] { return runner_ ? runner_->point() : step_; });
      return window(req);
    }
    case E::kHello:
    case E::kConfigure:
      throw ProtocolError(wire::Error::OUT_OF_ORDER,
                          what + " is only allowed once, at the start of a session");
    default:
      throw ProtocolError(wire::Error::BAD_REQUEST, "a node does not accept " + what + " messages");
  }
}

wire::Envelope NodeSession::on_hello(const wire::Envelope& req) {
  if (req.body_case() != wire::Envelope::kHello)
    throw ProtocolError(wire::Error::OUT_OF_ORDER,
                        "expected hello as the first message of a session, got " + body_name(req));
  const wire::Hello& h = req.hello();
  if (h.protocol_version() != kProtocolVersion)
    throw ProtocolError(wire::Error::VERSION_MISMATCH,
                        "protocol version " + std::to_string(h.protocol_version()) +
                            " is not supported; this node speaks version " +
                            std::to_string(kProtocolVersion));
  participant_ = h.participant();
  peer_hello_ = h.role() == "peer";
  peer_of_ = h.peer_of();
  fingerprint_ = h.scene_fingerprint();
  hello_nonce_ = h.nonce();
  // Before a node with a secret has its answer, it says nothing but the
  // challenge: not whom it serves, not its scene.
  if (options_.token) {
    nonce_ = random_nonce();
    state_ = State::kAwaitAuth;
    wire::Envelope reply;
    reply.set_id(req.id());
    reply.mutable_challenge()->set_nonce(nonce_);
    return reply;
  }
  check_hello_target();
  check_pinned_scene();
  state_ = State::kAwaitConfigure;
  return hello_reply(req.id());
}

wire::Envelope NodeSession::on_auth(const wire::Envelope& req) {
  const std::string nonce = std::move(nonce_);
  nonce_.clear();  // one answer per challenge
  const std::string expected = auth_answer(*options_.token, participant_, nonce);
  if (req.body_case() != wire::Envelope::kAuth || !constant_time_equal(req.auth().mac(), expected))
    throw ProtocolError(wire::Error::UNAUTHORIZED,
                        "this node requires the shared secret of its --token-file; the answer "
                        "to its challenge was missing or wrong");
  check_hello_target();
  check_pinned_scene();
  state_ = State::kAwaitConfigure;
  wire::Envelope reply = hello_reply(req.id());
  // The other half: the node proves to the master that it holds the secret.
  if (!hello_nonce_.empty())
    reply.mutable_hello_reply()->set_proof(
        auth_proof(*options_.token, participant_, hello_nonce_, nonce));
  return reply;
}

Scene NodeSession::configured_scene(const wire::Configure& c) const {
  if (c.participant() != participant_)
    throw ProtocolError(wire::Error::WRONG_ROLE, "configure names the " + c.participant() +
                                                     " participant, the hello the " + participant_);
  if (c.scene().empty())
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        "configure: this built-in node needs the scene (its text)");
  Scene scene = scene_from_wire(c);
  if (scene_fingerprint(scene) != fingerprint_)
    throw ProtocolError(wire::Error::SCENE_MISMATCH,
                        "the configured scene does not match the fingerprint of the hello");
  // Resource limits: a session cannot make the node allocate without bound.
  if (scene.sleeper_count > kMaxSleepers || scene.elements_per_span > kMaxElementsPerSpan)
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        "configure: the mesh exceeds this node's limits (" +
                            std::to_string(scene.sleeper_count) + " sleepers, " +
                            std::to_string(scene.elements_per_span) +
                            " elements per span; at most " + std::to_string(kMaxSleepers) +
                            " and " + std::to_string(kMaxElementsPerSpan) + ")");
  if (!(c.macro_step() > 0) || !(c.tolerance() > 0) || c.micro_steps() < 0 ||
      c.micro_steps() > 65536)
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        "configure: macro_step and tolerance must be positive, micro_steps "
                        "between 0 and 65536");
  return scene;
}

SubsystemConfig NodeSession::configured_subsystem(const Scene& scene,
                                                  const wire::Configure& c) const {
  std::vector<InterfaceSpec> interfaces;
  for (const auto& w : c.interfaces()) interfaces.push_back(from_wire(w));
  SubsystemConfig cfg;
  try {
    cfg.participant = participant_from_interfaces(scene, participant_, interfaces);
  } catch (const std::invalid_argument& e) {
    throw ProtocolError(wire::Error::BAD_INTERFACE,
                        "participant " + participant_ + ": " + e.what());
  }
  for (std::size_t k = 0; k < interfaces.size(); ++k)
    if (c.interfaces(static_cast<int>(k)).x_size() != interface_points(scene, interfaces[k]))
      throw ProtocolError(wire::Error::BAD_INTERFACE,
                          "participant " + participant_ + ": interface " +
                              c.interfaces(static_cast<int>(k)).cut() + " has " +
                              std::to_string(c.interfaces(static_cast<int>(k)).x_size()) +
                              " coupling points, the model " +
                              std::to_string(interface_points(scene, interfaces[k])));
  cfg.macro_step = c.macro_step();
  cfg.tolerance = c.tolerance();
  cfg.micro_steps = c.micro_steps();
  cfg.carry_acceleration = c.carry_acceleration();
  cfg.max_micro_steps = c.max_micro_steps() > 0
                            ? std::min<long>(c.max_micro_steps(), options_.max_micro_steps)
                            : options_.max_micro_steps;
  return cfg;
}

std::unique_ptr<Participant> NodeSession::built_participant(const wire::Configure& c) const {
  const Scene scene = configured_scene(c);
  const SubsystemConfig cfg = configured_subsystem(scene, c);
  return options_.make_participant ? options_.make_participant(scene, cfg)
                                   : std::make_unique<Subsystem>(scene, cfg);
}

wire::Envelope NodeSession::on_configure(const wire::Envelope& req) {
  if (req.body_case() != wire::Envelope::kConfigure)
    throw ProtocolError(wire::Error::OUT_OF_ORDER,
                        "expected configure after hello, got " + body_name(req));
  const wire::Configure& c = req.configure();
  try {
    served_ = options_.configure ? options_.configure(configured_setup(c)) : built_participant(c);
  } catch (const BadRequestError& e) {
    throw ProtocolError(wire::Error::BAD_REQUEST, "participant " + participant_ + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw ProtocolError(wire::Error::BAD_INTERFACE,
                        "participant " + participant_ + ": " + e.what());
  }
  if (!served_)
    throw ProtocolError(wire::Error::INTERNAL,
                        "participant " + participant_ + ": the program built no participant");
  macro_step_ = c.macro_step();
  progress_every_ = std::chrono::milliseconds(
      c.progress_ms() == 0 ? 0 : std::max<std::uint32_t>(c.progress_ms(), kMinProgressMs));
  in_shape_ = input_shape(c);
  // A step's samples: at its start and after each micro step.
  const long max_micro = c.max_micro_steps() > 0
                             ? std::min<long>(c.max_micro_steps(), options_.max_micro_steps)
                             : options_.max_micro_steps;
  max_samples_ =
      static_cast<std::size_t>(std::max<long>(max_micro, Newmark::kMaxStepsPerInterval)) + 1;
  description_ = served_->name();
  state_ = State::kConfigured;
  const Channels ch = served_->channels();
  if (const std::string why = check_declared_channels({{"this node", ch}}); !why.empty())
    throw ProtocolError(wire::Error::INTERNAL, why);
  wire::Envelope reply;
  reply.set_id(req.id());
  auto* w = reply.mutable_configured();
  for (const auto& h : ch.history) w->add_history(h);
  for (const auto& r : ch.results) w->add_results(r);
  return reply;
}

}  // namespace railcosim
