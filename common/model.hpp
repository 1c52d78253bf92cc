// The model as components and the elastic layers between them, and a
// co-simulation as a partition of it into participants.
//
// The components stack up in load order: vehicle, rail, sleepers, soil (the
// soil only when the scene has one). Between two neighbours lies an elastic
// layer, the only places a cut can go:
//
//   cut  layer            upper     lower     points               damped
//   wr   Hertz contact    vehicle   rail      1 per wheel, at v_0  no
//   rs   railpads         rail      sleepers  one per sleeper      yes
//   ss   ballast          sleepers  soil      one per sleeper      yes
//
// A cut has two sides. The upper side always receives the lower side's
// displacements (and velocities, through a damped layer) and computes the
// layer's force from its own state; the lower side receives displacements
// (X-X) or the force the upper side computed (X-T). A new cut is one more row
// of cut_kinds() and of the layer tables in track_model.cpp, not a new branch.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cosim_case.hpp"

namespace railcosim {

struct Scene;

// The components in load order. A new component is one enumerator here and
// one row of components() (and, if it bounds a participant of its own, of
// roles()); kComponentCount follows the enumerator list.
enum class Component { kVehicle, kRail, kSleepers, kSoil, kCount };
inline constexpr int kComponentCount = static_cast<int>(Component::kCount);

struct ComponentKind {
  Component id;
  const char* name;                     // "sleepers"
  bool (*present)(const Scene& scene);  // whether the scene models it
  const char* absent_hint;              // how a scene that lacks it adds it
};
// One row per component, in load order.
const std::vector<ComponentKind>& components();
std::string to_string(Component c);

// Which components a (sub)system holds.
struct Parts {
  std::array<bool, kComponentCount> held{};
  bool has(Component c) const { return held[static_cast<int>(c)]; }
  void add(Component c) { held[static_cast<int>(c)] = true; }
  static Parts all(const Scene& scene);  // the monolithic model
};

struct CutKind {
  const char* name;   // "wr"
  const char* title;  // "wheel/rail"
  Component upper, lower;
  bool moving;  // its coupling points move with the vehicle
  bool damped;  // displacement receivers also get velocities
};
const std::vector<CutKind>& cut_kinds();
// Index into cut_kinds(), or -1.
int find_cut(const std::string& name);
// The cuts' names in load order: "wr, rs, ss".
std::string cut_names();

enum class CutSide { kUpper, kLower };

enum class Quantity { kDisplacement, kVelocity, kForce };
std::string to_string(Quantity q);

// One side of one cut, as a participant sees it.
struct InterfaceSpec {
  int cut = 0;  // index into cut_kinds()
  CutSide side = CutSide::kUpper;
  Coupling coupling = Coupling::kXX;
  int peer = -1;          // index of the participant on the other side
  std::string peer_role;  // and its role

  const CutKind& kind() const { return cut_kinds()[static_cast<std::size_t>(cut)]; }
  bool receives_force() const { return side == CutSide::kLower && coupling == Coupling::kXT; }
  bool sends_force() const { return side == CutSide::kUpper && coupling == Coupling::kXT; }
  std::vector<Quantity> receives() const;
  std::vector<Quantity> sends() const;
};

// A participant of a co-simulation: the components it holds, and its
// interfaces (the cut above it first, then the cut below it).
struct ParticipantSpec {
  std::string role;  // "vehicle", "track", "rail", "soil"
  Parts parts;
  std::vector<InterfaceSpec> interfaces;
};

// The participants of a case, in load order. Throws std::invalid_argument if
// the cuts are not in load order or the scene lacks a component they need.
std::vector<ParticipantSpec> partition(const Scene& scene, const CaseSpec& spec);

// The participant that holds exactly the components between the given
// interfaces (what a node rebuilds from the interfaces it is told).
ParticipantSpec participant_from_interfaces(const Scene& scene, const std::string& role,
                                            const std::vector<InterfaceSpec>& interfaces);

// The participants a node can serve. A participant's role is the first row
// whose marker component it holds (so the vehicle's participant is "vehicle"
// whatever else it holds, one holding the sleepers but no vehicle "track").
struct RoleKind {
  const char* name;          // "track"
  Component marker;          // the component that names it
  const char* conform_case;  // the one-cut case `master conform` checks it in
};
const std::vector<RoleKind>& roles();
// The role names, in the order of roles(); the row of one, or nullptr.
std::vector<std::string> role_names();
const RoleKind* find_role(const std::string& name);

// The role name of a participant holding these components.
std::string role_of(const Parts& parts);

// Coupling points of a cut at t = 0 in the rail's frame (m).
std::vector<double> coupling_points(const Scene& scene, int cut);

// The area a coupling point stands for (see Footprint in railcosim.proto):
// centred on (x, y), `length` along the track, `width` across, z down from
// the surface of the cut.
struct Footprint {
  double x = 0, y = 0, z = 0, length = 0, width = 0;
};
// One per coupling point at the sleepers/soil cut (one rail's share of a
// sleeper bay on the soil's surface); empty at the other cuts.
std::vector<Footprint> footprints(const Scene& scene, int cut);

}  // namespace railcosim
