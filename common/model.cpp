#include "model.hpp"

#include <stdexcept>

#include "scene.hpp"

namespace railcosim {

namespace {

bool always(const Scene&) {
  return true;
}
bool soil_present(const Scene& scene) {
  return scene.has_soil();
}

}  // namespace

const std::vector<ComponentKind>& components() {
  static const std::vector<ComponentKind> kinds = {
      {Component::kVehicle, "vehicle", always, ""},
      {Component::kRail, "rail", always, ""},
      {Component::kSleepers, "sleepers", always, ""},
      {Component::kSoil, "soil", soil_present,
       "the scene's soil is fixed; set [soil] model = \"lumped\", \"external\" or \"fe\""},
  };
  return kinds;
}

std::string to_string(Component c) {
  for (const ComponentKind& k : components())
    if (k.id == c) return k.name;
  return "?";
}

const std::vector<RoleKind>& roles() {
  static const std::vector<RoleKind> kinds = {
      {"vehicle", Component::kVehicle, "wr-xx-jacobi"},
      {"track", Component::kSleepers, "wr-xx-jacobi"},
      {"rail", Component::kRail, "wr-xx+rs-xx-jacobi"},
      {"soil", Component::kSoil, "ss-xx-jacobi"},
  };
  return kinds;
}

std::vector<std::string> role_names() {
  std::vector<std::string> names;
  for (const RoleKind& r : roles()) names.emplace_back(r.name);
  return names;
}

const RoleKind* find_role(const std::string& name) {
  for (const RoleKind& r : roles())
    if (name == r.name) return &r;
  return nullptr;
}

std::string to_string(Quantity q) {
  switch (q) {
    case Quantity::kDisplacement:
      return "displacement";
    case Quantity::kVelocity:
      return "velocity";
    case Quantity::kForce:
      return "force";
  }
  return "?";
}

Parts Parts::all(const Scene& scene) {
  Parts p;
  for (const ComponentKind& k : components())
    if (k.present(scene)) p.add(k.id);
  return p;
}

const std::vector<CutKind>& cut_kinds() {
  static const std::vector<CutKind> kinds = {
      {"wr", "wheel/rail", Component::kVehicle, Component::kRail, true, false},
      {"rs", "rail/sleepers", Component::kRail, Component::kSleepers, false, true},
      {"ss", "sleepers/soil", Component::kSleepers, Component::kSoil, false, true},
  };
  return kinds;
}

int find_cut(const std::string& name) {
  const auto& k = cut_kinds();
  for (std::size_t i = 0; i < k.size(); ++i)
    if (name == k[i].name) return static_cast<int>(i);
  return -1;
}

std::string cut_names() {
  std::string names;
  for (const CutKind& k : cut_kinds()) names += (names.empty() ? "" : ", ") + std::string(k.name);
  return names;
}

std::vector<Quantity> InterfaceSpec::receives() const {
  if (receives_force()) return {Quantity::kForce};
  if (kind().damped) return {Quantity::kDisplacement, Quantity::kVelocity};
  return {Quantity::kDisplacement};
}

std::vector<Quantity> InterfaceSpec::sends() const {
  if (sends_force()) return {Quantity::kForce};
  if (kind().damped) return {Quantity::kDisplacement, Quantity::kVelocity};
  return {Quantity::kDisplacement};
}

std::string role_of(const Parts& parts) {
  for (const RoleKind& r : roles())
    if (parts.has(r.marker)) return r.name;
  return "?";
}

namespace {

// The last component the scene models (a participant below the last cut
// holds everything down to it).
Component last_component(const Scene& scene) {
  Component last = Component::kVehicle;
  for (const ComponentKind& k : components())
    if (k.present(scene)) last = k.id;
  return last;
}

// Why a cut cannot be made in this scene (a component on either side is
// not modelled), or "".
std::string absent(const Scene& scene, const CutKind& kind) {
  for (const ComponentKind& k : components())
    if ((k.id == kind.upper || k.id == kind.lower) && !k.present(scene))
      return std::string("needs the ") + k.name + " (" + k.absent_hint + ")";
  return "";
}

Parts range(Component first, Component last) {
  Parts p;
  for (int c = static_cast<int>(first); c <= static_cast<int>(last); ++c)
    p.add(static_cast<Component>(c));
  return p;
}

}  // namespace

std::vector<ParticipantSpec> partition(const Scene& scene, const CaseSpec& spec) {
  if (spec.monolithic) throw std::invalid_argument("the monolithic case has no participants");
  if (spec.cuts.empty()) throw std::invalid_argument("a co-simulation case needs a cut");
  bool cuts_soil = false;
  for (std::size_t k = 0; k < spec.cuts.size(); ++k) {
    const CutKind& kind = cut_kinds()[static_cast<std::size_t>(spec.cuts[k].cut)];
    if (k > 0 && spec.cuts[k].cut <= spec.cuts[k - 1].cut)
      throw std::invalid_argument("case " + spec.name() +
                                  ": the cuts must be distinct and in load order (" + cut_names() +
                                  ")");
    if (kind.lower == Component::kSoil) cuts_soil = true;
    if (const std::string missing = absent(scene, kind); !missing.empty())
      throw std::invalid_argument("case " + spec.name() + ": the " + kind.title + " cut (" +
                                  kind.name + ") " + missing);
  }
  if (scene.outside_vehicle() &&
      (spec.cuts.empty() ||
       cut_kinds()[static_cast<std::size_t>(spec.cuts.front().cut)].upper != Component::kVehicle))
    throw std::invalid_argument("case " + spec.name() +
                                ": the scene's vehicle is an FMU ([vehicle.fmu]), so the case must "
                                "cut at the wheel/rail contact (wr) to reach it");
  if (scene.outside_soil() && !cuts_soil)
    throw std::invalid_argument(
        "case " + spec.name() + ": the scene's soil is " +
        (scene.started_soil() != nullptr ? scene.started_soil()->title : "external") +
        ", so the case must cut through the ballast (ss) to reach it");

  std::vector<ParticipantSpec> out;
  Component first = Component::kVehicle;
  const int n = static_cast<int>(spec.cuts.size());
  for (int k = 0; k <= n; ++k) {
    ParticipantSpec p;
    const Component last =
        k < n ? cut_kinds()[static_cast<std::size_t>(spec.cuts[static_cast<std::size_t>(k)].cut)]
                    .upper
              : last_component(scene);
    p.parts = range(first, last);
    p.role = role_of(p.parts);
    if (k > 0) {
      const CutChoice& c = spec.cuts[static_cast<std::size_t>(k - 1)];
      p.interfaces.push_back({c.cut, CutSide::kLower, c.coupling, k - 1, ""});
    }
    if (k < n) {
      const CutChoice& c = spec.cuts[static_cast<std::size_t>(k)];
      p.interfaces.push_back({c.cut, CutSide::kUpper, c.coupling, k + 1, ""});
      first = cut_kinds()[static_cast<std::size_t>(c.cut)].lower;
    }
    out.push_back(std::move(p));
  }
  for (ParticipantSpec& p : out)
    for (InterfaceSpec& i : p.interfaces) i.peer_role = out[static_cast<std::size_t>(i.peer)].role;
  return out;
}

ParticipantSpec participant_from_interfaces(const Scene& scene, const std::string& role,
                                            const std::vector<InterfaceSpec>& interfaces) {
  Component first = Component::kVehicle, last = last_component(scene);
  int above = 0, below = 0;
  for (const InterfaceSpec& i : interfaces) {
    if (i.cut < 0 || i.cut >= static_cast<int>(cut_kinds().size()))
      throw std::invalid_argument("unknown cut index " + std::to_string(i.cut));
    if (i.side == CutSide::kLower) {
      first = i.kind().lower;
      ++above;
    } else {
      last = i.kind().upper;
      ++below;
    }
    if (const std::string missing = absent(scene, i.kind()); !missing.empty())
      throw std::invalid_argument(std::string("interface ") + i.kind().name + " " + missing);
  }
  if (above > 1 || below > 1 || static_cast<int>(first) > static_cast<int>(last))
    throw std::invalid_argument("the interfaces do not bound one contiguous set of components");
  ParticipantSpec p;
  p.parts = range(first, last);
  p.role = role_of(p.parts);
  if (!role.empty() && role != p.role) {
    std::string msg = "the interfaces";
    for (const InterfaceSpec& i : interfaces) {
      msg += ' ';
      msg += i.kind().name;
      msg += i.side == CutSide::kLower ? " (lower side)" : " (upper side)";
    }
    msg += " describe the " + p.role + " participant, not the " + role + " participant";
    throw std::invalid_argument(msg);
  }
  p.interfaces = interfaces;
  return p;
}

std::vector<double> coupling_points(const Scene& scene, int cut) {
  const CutKind& kind = cut_kinds()[static_cast<std::size_t>(cut)];
  if (kind.moving) {
    // One point per wheel, front to back, where it stands at t = 0.
    std::vector<double> x;
    for (double offset : scene.wheel_offsets()) x.push_back(scene.initial_position + offset);
    return x;
  }
  std::vector<double> x(static_cast<std::size_t>(scene.sleeper_count));
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = (static_cast<double>(i) + 0.5) * scene.sleeper_spacing;
  return x;
}

std::vector<Footprint> footprints(const Scene& scene, int cut) {
  std::vector<Footprint> f;
  if (std::string(cut_kinds()[static_cast<std::size_t>(cut)].name) != "ss") return f;
  for (double x : coupling_points(scene, cut))
    f.push_back(
        {x, scene.sleeper_length / 4, 0.0, scene.sleeper_spacing, scene.sleeper_length / 2});
  return f;
}

}  // namespace railcosim
