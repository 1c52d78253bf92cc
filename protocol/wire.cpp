#include "wire.hpp"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

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
    case wire::Envelope::BODY_NOT_SET:
      break;
  }
  return "empty";
}

wire::Envelope hello_envelope(wire::Role expected_peer, std::uint64_t scene_fingerprint,
                              std::uint32_t protocol_version) {
  wire::Envelope e;
  auto* h = e.mutable_hello();
  h->set_protocol_version(protocol_version);
  h->set_role(wire::ROLE_MASTER);
  h->set_expected_peer(expected_peer);
  h->set_scene_fingerprint(scene_fingerprint);
  h->set_name("master");
  return e;
}

wire::Envelope configure_envelope(const Scene& scene, Split split, Coupling coupling,
                                  double macro_step, double tolerance) {
  wire::Envelope e;
  auto* c = e.mutable_configure();
  *c->mutable_scene() = to_wire(scene);
  c->set_split(to_wire(split));
  c->set_coupling(to_wire(coupling));
  c->set_macro_step(macro_step);
  c->set_tolerance(tolerance);
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

wire::SceneParams to_wire(const Scene& s) {
  wire::SceneParams p;
  p.set_name(s.name);
  p.set_vehicle_mass(s.vehicle_mass);
  p.set_hertz_constant(s.hertz_constant);
  p.set_speed(s.speed);
  p.set_initial_position(s.initial_position);
  p.set_young_modulus(s.young_modulus);
  p.set_second_moment(s.second_moment);
  p.set_area(s.area);
  p.set_density(s.density);
  p.set_elements_per_span(s.elements_per_span);
  p.set_pad_stiffness(s.pad_stiffness);
  p.set_pad_damping(s.pad_damping);
  p.set_sleeper_mass(s.sleeper_mass);
  p.set_sleeper_spacing(s.sleeper_spacing);
  p.set_sleeper_count(s.sleeper_count);
  p.set_ballast_stiffness(s.ballast_stiffness);
  p.set_ballast_damping(s.ballast_damping);
  p.set_soil_model(s.soil_model);
  p.set_gravity(s.gravity);
  p.set_end_time(s.end_time);
  p.set_macro_step(s.macro_step);
  p.set_tolerance(s.tolerance);
  p.set_divergence_factor(s.divergence_factor);
  p.set_amplification_threshold(s.amplification_threshold);
  p.set_rail_start(s.rail_start);
  return p;
}

Scene from_wire(const wire::SceneParams& p, const std::string& source) {
  Scene s;
  s.source = source;
  s.name = p.name();
  s.vehicle_mass = p.vehicle_mass();
  s.hertz_constant = p.hertz_constant();
  s.speed = p.speed();
  s.initial_position = p.initial_position();
  s.young_modulus = p.young_modulus();
  s.second_moment = p.second_moment();
  s.area = p.area();
  s.density = p.density();
  s.elements_per_span = p.elements_per_span();
  s.pad_stiffness = p.pad_stiffness();
  s.pad_damping = p.pad_damping();
  s.sleeper_mass = p.sleeper_mass();
  s.sleeper_spacing = p.sleeper_spacing();
  s.sleeper_count = p.sleeper_count();
  s.ballast_stiffness = p.ballast_stiffness();
  s.ballast_damping = p.ballast_damping();
  s.soil_model = p.soil_model();
  s.gravity = p.gravity();
  s.end_time = p.end_time();
  s.macro_step = p.macro_step();
  s.tolerance = p.tolerance();
  s.divergence_factor = p.divergence_factor();
  s.amplification_threshold = p.amplification_threshold();
  s.rail_start = p.rail_start();
  try {
    s.validate();
  } catch (const SceneError& e) {
    throw ProtocolError(wire::Error::BAD_SCENE, e.what());
  }
  return s;
}

std::uint64_t scene_fingerprint(const Scene& scene) {
  // Deterministic serialisation, then 64-bit FNV-1a over the bytes.
  const wire::SceneParams p = to_wire(scene);
  std::string bytes;
  {
    google::protobuf::io::StringOutputStream raw(&bytes);
    google::protobuf::io::CodedOutputStream out(&raw);
    out.SetSerializationDeterministic(true);
    p.SerializeToCodedStream(&out);
  }
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

wire::CouplingData to_wire(const CouplingData& d) {
  wire::CouplingData w;
  const std::size_t n = std::max({d.displacement.size(), d.velocity.size(), d.force.size()});
  for (std::size_t i = 0; i < n; ++i) {
    auto* p = w.add_points();
    if (i < d.displacement.size()) p->set_displacement(d.displacement[i]);
    if (i < d.velocity.size()) p->set_velocity(d.velocity[i]);
    if (i < d.force.size()) p->set_force(d.force[i]);
  }
  return w;
}

CouplingData from_wire(const wire::CouplingData& w) {
  CouplingData d;
  if (w.points_size() == 0) return d;
  const auto& first = w.points(0);
  const bool has_d = first.has_displacement(), has_v = first.has_velocity(),
             has_f = first.has_force();
  for (const auto& p : w.points()) {
    if (p.has_displacement() != has_d || p.has_velocity() != has_v || p.has_force() != has_f)
      throw ProtocolError(wire::Error::BAD_REQUEST,
                          "coupling points carry different quantities; every point of a "
                          "message must carry the same");
    if (has_d) d.displacement.push_back(p.displacement());
    if (has_v) d.velocity.push_back(p.velocity());
    if (has_f) d.force.push_back(p.force());
  }
  return d;
}

wire::StepReport to_wire(const StepResult& r, long step, double t) {
  wire::StepReport w;
  w.set_step(step);
  w.set_t(t);
  *w.mutable_outputs() = to_wire(r.outputs);
  w.set_max_abs_displacement(r.max_abs_displacement);
  w.set_finite(r.finite);
  if (r.row) {
    auto* row = w.mutable_row();
    row->set_t(r.row->t);
    row->set_wheel(r.row->wheel);
    row->set_contact_force(r.row->contact_force);
  }
  return w;
}

StepResult from_wire(const wire::StepReport& w) {
  StepResult r;
  r.outputs = from_wire(w.outputs());
  r.max_abs_displacement = w.max_abs_displacement();
  r.finite = w.finite();
  if (w.has_row()) r.row = HistoryRow{w.row().t(), w.row().wheel(), w.row().contact_force()};
  return r;
}

wire::Split to_wire(Split s) {
  return s == Split::kWheelRail ? wire::SPLIT_WHEEL_RAIL : wire::SPLIT_RAIL_SLEEPERS;
}
wire::Coupling to_wire(Coupling c) {
  return c == Coupling::kXX ? wire::COUPLING_XX : wire::COUPLING_XT;
}
Split from_wire(wire::Split s) {
  if (s == wire::SPLIT_WHEEL_RAIL) return Split::kWheelRail;
  if (s == wire::SPLIT_RAIL_SLEEPERS) return Split::kRailSleepers;
  throw ProtocolError(wire::Error::BAD_REQUEST, "configure: split is missing or unknown");
}
Coupling from_wire(wire::Coupling c) {
  if (c == wire::COUPLING_XX) return Coupling::kXX;
  if (c == wire::COUPLING_XT) return Coupling::kXT;
  throw ProtocolError(wire::Error::BAD_REQUEST, "configure: coupling is missing or unknown");
}

wire::Role role_of(Side side) {
  return side == Side::kS1 ? wire::ROLE_VEHICLE : wire::ROLE_TRACK;
}

std::string role_name(wire::Role role) {
  switch (role) {
    case wire::ROLE_MASTER:
      return "master";
    case wire::ROLE_VEHICLE:
      return "vehicle (S1)";
    case wire::ROLE_TRACK:
      return "track (S2)";
    default:
      return "unspecified";
  }
}

}  // namespace railcosim
