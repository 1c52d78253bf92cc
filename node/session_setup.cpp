// Configure for a participant built from what the master says of it
// (NodeOptions::configure): its interfaces, the run's settings and its own
// configuration, without reading the scene.
#include <algorithm>
#include <cmath>

#include "session.hpp"
#include "setup_from_configure.hpp"

namespace railcosim {
namespace {

std::vector<Quantity> quantities(const google::protobuf::RepeatedField<int>& wire_quantities,
                                 const std::string& where) {
  std::vector<Quantity> out;
  for (int q : wire_quantities) {
    switch (q) {
      case wire::DISPLACEMENT:
        out.push_back(Quantity::kDisplacement);
        break;
      case wire::VELOCITY:
        out.push_back(Quantity::kVelocity);
        break;
      case wire::FORCE:
        out.push_back(Quantity::kForce);
        break;
      default:
        throw ProtocolError(wire::Error::BAD_REQUEST,
                            where + ": quantity " + std::to_string(q) +
                                " is none of DISPLACEMENT, VELOCITY, FORCE");
    }
  }
  return out;
}

Interface interface_from_wire(const wire::Interface& w, std::size_t k) {
  const std::string where = "configure: interface " + std::to_string(k) + " (" + w.cut() + ")";
  Interface i;
  i.cut = w.cut();
  i.peer = w.peer();
  i.upper = w.upper();
  i.x.assign(w.x().begin(), w.x().end());
  i.speed = w.speed();
  i.receives = quantities(w.receives(), where + " receives");
  i.sends = quantities(w.sends(), where + " sends");
  i.stiffness = w.stiffness();
  i.damping = w.damping();
  i.hertz_constant = w.hertz_constant();
  for (const wire::Footprint& f : w.footprints())
    i.footprints.push_back({f.x(), f.y(), f.z(), f.length(), f.width()});
  const bool finite =
      std::all_of(i.x.begin(), i.x.end(), [](double x) { return std::isfinite(x); }) &&
      std::isfinite(i.speed) && std::isfinite(i.stiffness) && std::isfinite(i.damping) &&
      std::isfinite(i.hertz_constant);
  if (!finite) throw ProtocolError(wire::Error::BAD_REQUEST, where + ": a value is not finite");
  if (!i.footprints.empty() && i.footprints.size() != i.x.size())
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        where + ": " + std::to_string(i.footprints.size()) + " footprints for " +
                            std::to_string(i.x.size()) + " coupling points");
  return i;
}

}  // namespace

ParticipantSetup setup_from_configure(const wire::Configure& c, const std::string& participant,
                                      long max_micro_steps) {
  if (!(c.macro_step() > 0) || !(c.tolerance() >= 0) || c.micro_steps() < 0 ||
      c.micro_steps() > 65536)
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        "configure: macro_step must be positive, tolerance not negative, "
                        "micro_steps between 0 and 65536");
  ParticipantSetup s;
  s.participant = participant;
  for (int k = 0; k < c.interfaces_size(); ++k)
    s.interfaces.push_back(interface_from_wire(c.interfaces(k), static_cast<std::size_t>(k)));
  s.run.macro_step = c.macro_step();
  s.run.end_time = c.end_time();
  s.run.tolerance = c.tolerance();
  s.run.micro_steps = c.micro_steps();
  s.run.max_micro_steps = c.max_micro_steps() > 0
                              ? std::min<long>(c.max_micro_steps(), max_micro_steps)
                              : max_micro_steps;
  s.run.carry_acceleration = c.carry_acceleration();
  return s;
}

ParticipantSetup NodeSession::configured_setup(const wire::Configure& c) const {
  if (c.participant() != participant_)
    throw ProtocolError(wire::Error::WRONG_ROLE, "configure names the " + c.participant() +
                                                     " participant, the hello the " + participant_);
  if (options_.pinned_scene) {  // the scene of the hello, which the pinned one matched
    Scene sent;
    sent.text = c.scene();
    for (const wire::SceneFile& f : c.scene_files()) sent.files[f.name()] = f.contents();
    if (scene_fingerprint(sent) != fingerprint_)
      throw ProtocolError(wire::Error::SCENE_MISMATCH,
                          "the configured scene does not match the fingerprint of the hello");
  }
  ParticipantSetup s = setup_from_configure(c, participant_, options_.max_micro_steps);
  if (const auto& file = options_.config_file)
    s.config = OwnConfig::table_of(file->text, file->path,
                                   file->table.empty() ? participant_ : file->table);
  else if (!c.own_config().empty())
    s.config = OwnConfig::parse(c.own_config(), "the master's scene", participant_);
  else
    s.config =
        OwnConfig("no --config FILE, and the master's scene sends no [" + participant_ + "] table",
                  participant_);
  return s;
}

}  // namespace railcosim
