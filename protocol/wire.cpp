#include "wire.hpp"

#include <algorithm>

#include "scene_text.hpp"

namespace railcosim {

std::string encode_frame(const wire::Envelope& envelope, std::size_t max_bytes) {
  const std::size_t n = envelope.ByteSizeLong();
  if (n > max_bytes)
    throw ProtocolError(wire::Error::FRAME_TOO_LARGE,
                        "a " + body_name(envelope) + " message of " + std::to_string(n) +
                            " bytes exceeds the frame limit of " + std::to_string(max_bytes));
  std::string out(kFrameHeaderBytes + n, '\0');
  const auto len = static_cast<std::uint32_t>(n);
  out[0] = static_cast<char>((len >> 24) & 0xff);
  out[1] = static_cast<char>((len >> 16) & 0xff);
  out[2] = static_cast<char>((len >> 8) & 0xff);
  out[3] = static_cast<char>(len & 0xff);
  envelope.SerializeWithCachedSizesToArray(
      reinterpret_cast<std::uint8_t*>(out.data() + kFrameHeaderBytes));
  return out;
}

std::uint32_t decode_frame_length(const unsigned char h[kFrameHeaderBytes]) {
  return (std::uint32_t{h[0]} << 24) | (std::uint32_t{h[1]} << 16) | (std::uint32_t{h[2]} << 8) |
         std::uint32_t{h[3]};
}

std::uint32_t FrameDecoder::announced() const {
  if (buffer_.size() < kFrameHeaderBytes) return 0;
  return decode_frame_length(reinterpret_cast<const unsigned char*>(buffer_.data()));
}

FrameDecoder::Status FrameDecoder::next(wire::Envelope& out) {
  if (buffer_.size() < kFrameHeaderBytes) return Status::kNeedMore;
  const std::uint32_t len = announced();
  if (len > max_) return Status::kTooLarge;
  if (buffer_.size() < kFrameHeaderBytes + len) return Status::kNeedMore;
  out.Clear();
  const bool ok = out.ParseFromArray(buffer_.data() + kFrameHeaderBytes, static_cast<int>(len));
  buffer_.erase(0, kFrameHeaderBytes + len);
  if (!ok || out.body_case() == wire::Envelope::BODY_NOT_SET) return Status::kBadFrame;
  return Status::kFrame;
}

std::string body_name(const wire::Envelope& e) {
  switch (e.body_case()) {
    case wire::Envelope::kHello:
      return "hello";
    case wire::Envelope::kHelloReply:
      return "hello_reply";
    case wire::Envelope::kConfigure:
      return "configure";
    case wire::Envelope::kAck:
      return "ack";
    case wire::Envelope::kInitialize:
      return "initialize";
    case wire::Envelope::kStepReport:
      return "step_report";
    case wire::Envelope::kSetInputs:
      return "set_inputs";
    case wire::Envelope::kStep:
      return "step";
    case wire::Envelope::kGetOutputs:
      return "get_outputs";
    case wire::Envelope::kOutputs:
      return "outputs";
    case wire::Envelope::kGetResults:
      return "get_results";
    case wire::Envelope::kResults:
      return "results";
    case wire::Envelope::kSave:
      return "save";
    case wire::Envelope::kState:
      return "state";
    case wire::Envelope::kRestore:
      return "restore";
    case wire::Envelope::kShutdown:
      return "shutdown";
    case wire::Envelope::kError:
      return "error";
    case wire::Envelope::kChallenge:
      return "challenge";
    case wire::Envelope::kAuth:
      return "auth";
    case wire::Envelope::kConfigured:
      return "configured";
    case wire::Envelope::kStatics:
      return "statics";
    case wire::Envelope::kLinks:
      return "links";
    case wire::Envelope::kWindow:
      return "window";
    case wire::Envelope::kReports:
      return "reports";
    case wire::Envelope::kWindowDone:
      return "window_done";
    case wire::Envelope::kPeerData:
      return "peer_data";
    case wire::Envelope::kRecordSamples:
      return "record_samples";
    case wire::Envelope::kProgress:
      return "progress";
    case wire::Envelope::BODY_NOT_SET:
      break;
  }
  return "empty";
}

wire::Envelope hello_envelope(const std::string& participant, std::uint64_t scene_fingerprint,
                              std::uint32_t protocol_version) {
  wire::Envelope e;
  auto* h = e.mutable_hello();
  h->set_protocol_version(protocol_version);
  h->set_role("master");
  h->set_participant(participant);
  h->set_scene_fingerprint(scene_fingerprint);
  h->set_name("master");
  return e;
}

wire::Envelope configure_envelope(const Scene& scene, const SubsystemConfig& config,
                                  bool with_model) {
  wire::Envelope e;
  auto* c = e.mutable_configure();
  c->set_participant(config.participant.role);
  for (const InterfaceSpec& i : config.participant.interfaces)
    *c->add_interfaces() = to_wire(scene, i);
  c->set_macro_step(config.macro_step);
  c->set_end_time(scene.end_time);
  c->set_tolerance(config.tolerance);
  c->set_micro_steps(config.micro_steps);
  c->set_carry_acceleration(config.carry_acceleration);
  if (with_model) {
    check_scene_text(scene);  // the node parses the text: it must be the scene run here
    c->set_scene(scene.text);
    for (const auto& [name, contents] : scene.files) {
      wire::SceneFile* f = c->add_scene_files();
      f->set_name(name);
      f->set_contents(contents);
    }
  }
  if (config.participant.role == "soil") c->set_own_config(scene.soil_config);
  if (config.participant.role == "vehicle") c->set_own_config(scene.vehicle.fmu_config);
  return e;
}

wire::Envelope error_envelope(std::uint64_t id, wire::Error::Code code, const std::string& message,
                              long step, double t) {
  wire::Envelope e;
  e.set_id(id);
  auto* err = e.mutable_error();
  err->set_code(code);
  err->set_message(message);
  err->set_step(step);
  err->set_t(t);
  return e;
}

Scene scene_from_wire(const wire::Configure& c) {
  SceneFiles files;
  for (const wire::SceneFile& f : c.scene_files()) files[f.name()] = f.contents();
  try {
    Scene scene = parse_scene(c.scene(), "the master's scene", &files);
    // The text as sent: its fingerprint is the master's whatever version of
    // the TOML writer this node was built with.
    scene.text = c.scene();
    return scene;
  } catch (const SceneError& e) {
    throw ProtocolError(wire::Error::BAD_SCENE, e.what());
  }
}

std::uint64_t scene_fingerprint(const Scene& scene) {
  std::string bytes = scene.text;
  for (const auto& [name, contents] : scene.files) {
    bytes += '\0';
    bytes += name;
    bytes += '\0';
    bytes += contents;
  }
  return fnv1a64(bytes);
}

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 14695981039346656037ull;  // the FNV-1a 64-bit offset basis
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;  // the FNV 64-bit prime
  }
  return h;
}

namespace {

wire::Quantity to_wire(Quantity q) {
  switch (q) {
    case Quantity::kDisplacement:
      return wire::DISPLACEMENT;
    case Quantity::kVelocity:
      return wire::VELOCITY;
    case Quantity::kForce:
      return wire::FORCE;
  }
  return wire::QUANTITY_UNSPECIFIED;
}

std::string quantity_list(const std::vector<Quantity>& qs) {
  std::string s;
  for (Quantity q : qs) {
    if (!s.empty()) s += ", ";
    s += to_string(q);
  }
  return s.empty() ? "nothing" : s;
}

}  // namespace

wire::Interface to_wire(const Scene& scene, const InterfaceSpec& i) {
  wire::Interface w;
  w.set_cut(i.kind().name);
  w.set_peer(i.peer_role);
  w.set_upper(i.side == CutSide::kUpper);
  for (double x : coupling_points(scene, i.cut)) w.add_x(x);
  w.set_speed(i.kind().moving ? scene.speed : 0.0);
  for (Quantity q : i.receives()) w.add_receives(to_wire(q));
  for (Quantity q : i.sends()) w.add_sends(to_wire(q));
  const SpringDamper e = layer_element(scene, i.cut);
  w.set_stiffness(e.k);
  w.set_damping(e.c);
  if (i.kind().moving) w.set_hertz_constant(scene.hertz_constant);
  for (const Footprint& f : footprints(scene, i.cut)) {
    auto* o = w.add_footprints();
    o->set_x(f.x);
    o->set_y(f.y);
    o->set_z(f.z);
    o->set_length(f.length);
    o->set_width(f.width);
  }
  return w;
}

InterfaceSpec from_wire(const wire::Interface& w) {
  InterfaceSpec i;
  i.cut = find_cut(w.cut());
  if (i.cut < 0)
    throw ProtocolError(wire::Error::BAD_INTERFACE,
                        "interface '" + w.cut() + "': not a cut of this model (known: wr, rs, ss)");
  i.side = w.upper() ? CutSide::kUpper : CutSide::kLower;
  i.peer_role = w.peer();
  const bool gets_force =
      std::find(w.receives().begin(), w.receives().end(), wire::FORCE) != w.receives().end();
  const bool sends_force =
      std::find(w.sends().begin(), w.sends().end(), wire::FORCE) != w.sends().end();
  i.coupling = gets_force || sends_force ? Coupling::kXT : Coupling::kXX;
  auto same = [](const auto& got, const std::vector<Quantity>& want) {
    if (got.size() != static_cast<int>(want.size())) return false;
    for (int k = 0; k < got.size(); ++k)
      if (got[k] != to_wire(want[static_cast<std::size_t>(k)])) return false;
    return true;
  };
  if (!same(w.receives(), i.receives()) || !same(w.sends(), i.sends()))
    throw ProtocolError(wire::Error::BAD_INTERFACE,
                        "interface '" + w.cut() + "' (" + (w.upper() ? "upper" : "lower") +
                            " side): the built-in model receives " + quantity_list(i.receives()) +
                            " and sends " + quantity_list(i.sends()) + " there");
  return i;
}

void to_wire(const InterfaceData& i, wire::InterfaceData* o) {
  o->mutable_displacement()->Add(i.displacement.begin(), i.displacement.end());
  o->mutable_velocity()->Add(i.velocity.begin(), i.velocity.end());
  o->mutable_force()->Add(i.force.begin(), i.force.end());
}

wire::CouplingData to_wire(const CouplingData& d) {
  wire::CouplingData w;
  for (const InterfaceData& i : d) to_wire(i, w.add_interfaces());
  return w;
}

CouplingData from_wire(const wire::CouplingData& w) {
  CouplingData d;
  d.reserve(static_cast<std::size_t>(w.interfaces_size()));
  for (const auto& i : w.interfaces())
    d.push_back({{i.displacement().begin(), i.displacement().end()},
                 {i.velocity().begin(), i.velocity().end()},
                 {i.force().begin(), i.force().end()}});
  return d;
}

wire::StepReport to_wire(const StepResult& r, long step, double t) {
  wire::StepReport w;
  w.set_step(step);
  w.set_t(t);
  *w.mutable_outputs() = to_wire(r.outputs);
  w.set_max_abs_displacement(r.max_abs_displacement);
  w.set_finite(r.finite);
  w.mutable_history()->Add(r.history.begin(), r.history.end());
  return w;
}

StepResult from_wire(const wire::StepReport& w) {
  StepResult r;
  r.outputs = from_wire(w.outputs());
  r.max_abs_displacement = w.max_abs_displacement();
  r.finite = w.finite();
  r.history.assign(w.history().begin(), w.history().end());
  return r;
}

}  // namespace railcosim
