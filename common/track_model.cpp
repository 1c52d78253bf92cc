#include "track_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>

#include "resilient_layers.hpp"

namespace railcosim {

DofLayout make_layout(const Scene& scene, const Parts& parts) {
  DofLayout l;
  l.elements_per_span = scene.elements_per_span;
  l.element_length = scene.element_length();
  const bool rail = parts.has(Component::kRail), sleepers = parts.has(Component::kSleepers),
             soil = parts.has(Component::kSoil);
  int next = 0;
  if (parts.has(Component::kVehicle)) {
    // The vehicle first, numbered so that its band stays narrow: the car
    // as front wheelsets, front bogie, body, rear bogie, rear wheelsets
    // (half-bandwidth 3), a train's cars so one after the other (no term
    // couples two cars); the other models in their own order.
    const VehicleModel v = scene.vehicle_model();
    l.vehicle.resize(static_cast<std::size_t>(v.dofs()));
    const VehicleType type = scene.vehicle.type;
    if (type == VehicleType::car || type == VehicleType::train) {
      // Model order: body z, phi, bogie 1 z, phi, bogie 2 z, phi, wheelsets 1-4.
      static constexpr int kCarOrder[10] = {4, 5, 2, 3, 6, 7, 0, 1, 8, 9};
      for (int i = 0; i < v.dofs(); ++i)
        l.vehicle[static_cast<std::size_t>(i)] = i - i % 10 + kCarOrder[i % 10];
      next = v.dofs();
    } else {
      for (auto& d : l.vehicle) d = next++;
    }
    for (const WheelDof& w : v.wheels())
      l.wheels.push_back(l.vehicle[static_cast<std::size_t>(w.dof)]);
    l.wheel = l.wheels.front();
  }
  const auto n = static_cast<std::size_t>(scene.sleeper_count);
  if (sleepers) l.sleeper.assign(n, -1);
  if (sleepers && scene.sleeper_pad) l.pad_base.assign(n, -1);
  if (sleepers && scene.ballast_mat) l.mat_top.assign(n, -1);
  if (soil) l.soil.assign(n, -1);
  // The sleeper, the layers' interfaces and the soil of support i, numbered
  // next to each other.
  auto support = [&](int i) {
    const auto s = static_cast<std::size_t>(i);
    if (sleepers) l.sleeper[s] = next++;
    if (!l.pad_base.empty()) l.pad_base[s] = next++;
    if (!l.mat_top.empty()) l.mat_top[s] = next++;
    if (soil) l.soil[s] = next++;
  };
  if (rail) {
    const int nodes = scene.rail_nodes();
    l.rail_w.resize(static_cast<std::size_t>(nodes));
    l.rail_theta.resize(static_cast<std::size_t>(nodes));
    for (int k = 0; k < nodes; ++k) {
      l.rail_w[static_cast<std::size_t>(k)] = next++;
      l.rail_theta[static_cast<std::size_t>(k)] = next++;
      const int half = scene.elements_per_span / 2;
      if (k % scene.elements_per_span == half) {
        const int i = k / scene.elements_per_span;
        if (i < scene.sleeper_count) support(i);
      }
    }
  } else {
    for (int i = 0; i < scene.sleeper_count; ++i) support(i);
  }
  l.size = next;
  return l;
}

std::vector<int> layer_dofs(const DofLayout& l, int cut, CutSide side) {
  const std::string name = cut_kinds()[static_cast<std::size_t>(cut)].name;
  std::vector<int> out;
  if (name == "rs") {
    if (side == CutSide::kLower) return l.sleeper;
    const int sleepers = (static_cast<int>(l.rail_w.size()) - 1) / l.elements_per_span;
    for (int i = 0; i < sleepers; ++i)
      out.push_back(l.rail_w[static_cast<std::size_t>(l.pad_node(i))]);
    return out;
  }
  if (name == "ss") return side == CutSide::kUpper ? l.track_base() : l.soil;
  return out;  // the contact has no fixed DOFs
}

SpringDamper layer_element(const Scene& scene, int cut) {
  const std::string name = cut_kinds()[static_cast<std::size_t>(cut)].name;
  if (name == "rs") return {scene.pad_stiffness, scene.pad_damping};
  if (name == "ss")
    return scene.ballast_mat ? layer_spring(*scene.ballast_mat)
                             : SpringDamper{scene.ballast_stiffness, scene.ballast_damping};
  return {};
}

ContactPoint ContactPath::at(double t) const {
  const double x = position(t);
  const double s = x / element_length;
  int e = static_cast<int>(std::floor(s));
  e = std::clamp(e, 0, elements - 1);
  ContactPoint p;
  p.element = e;
  p.shape = hermite_shape(s - e, element_length);
  return p;
}

ContactPath contact_path(const Scene& scene, int wheel) {
  ContactPath p;
  p.x0 = scene.initial_position + scene.wheel_offsets()[static_cast<std::size_t>(wheel)];
  p.speed = scene.speed;
  p.element_length = scene.element_length();
  p.elements = scene.rail_nodes() - 1;
  return p;
}

int ContactTerm::entries(double t, const DofLayout& layout, Entry out[5]) const {
  int n = 0;
  if (has_wheel) out[n++] = {layout.wheels[static_cast<std::size_t>(wheel)], 1.0};
  if (has_rail) {
    const ContactPoint p = path.at(t);
    const int e = p.element;
    out[n++] = {layout.rail_w[e], -p.shape[0]};
    out[n++] = {layout.rail_theta[e], -p.shape[1]};
    out[n++] = {layout.rail_w[e + 1], -p.shape[2]};
    out[n++] = {layout.rail_theta[e + 1], -p.shape[3]};
  }
  return n;
}

namespace {

struct Triplet {
  int i, j;
  double m, c, k;
};
// Lower or upper entries of the three matrices; add() mirrors them.
using Triplets = std::vector<Triplet>;

void add_vehicle(const VehicleModel& vehicle, const DofLayout& l, Triplets& t) {
  const auto& M = vehicle.mass();
  const auto& C = vehicle.damping();
  const auto& K = vehicle.stiffness();
  for (int a = 0; a < vehicle.dofs(); ++a)
    for (int b = 0; b <= a; ++b) {
      const int i = l.vehicle[static_cast<std::size_t>(a)],
                j = l.vehicle[static_cast<std::size_t>(b)];
      if (a == b || M(a, b) != 0 || C(a, b) != 0 || K(a, b) != 0)
        t.push_back({std::max(i, j), std::min(i, j), M(a, b), C(a, b), K(a, b)});
    }
}

void add_rail(const Scene& scene, const DofLayout& l, Triplets& t) {
  const double L = scene.element_length();
  const Matrix4 ke = beam_stiffness(scene.young_modulus * scene.second_moment, L);
  const Matrix4 me = beam_consistent_mass(scene.density * scene.area, L);
  for (std::size_t e = 0; e + 1 < l.rail_w.size(); ++e) {
    const int dofs[4] = {l.rail_w[e], l.rail_theta[e], l.rail_w[e + 1], l.rail_theta[e + 1]};
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b <= a; ++b) t.push_back({dofs[a], dofs[b], me(a, b), 0, ke(a, b)});
  }
}

// A spring and damper between two DOFs.
void add_element(int upper, int lower, const SpringDamper& e, Triplets& t) {
  t.push_back({upper, upper, 0, e.c, e.k});
  t.push_back({lower, lower, 0, e.c, e.k});
  t.push_back({std::max(upper, lower), std::min(upper, lower), 0, -e.c, -e.k});
}

// The supports with resilient layers: sleeper, [pad, pad base,] ballast,
// [mat top, mat,] and the lowest element to the ground with a fixed soil
// (with a soil, add_layers places it: it is the ss cut's).
void add_layered_supports(const Scene& scene, const DofLayout& l, Triplets& t) {
  const SpringDamper ballast{scene.ballast_stiffness, scene.ballast_damping};
  const double m_i = interface_mass(scene);
  for (std::size_t i = 0; i < l.sleeper.size(); ++i) {
    t.push_back({l.sleeper[i], l.sleeper[i], scene.sleeper_mass, 0, 0});
    int top = l.sleeper[i];  // the DOF over the next element down
    if (scene.sleeper_pad) {
      t.push_back({l.pad_base[i], l.pad_base[i], m_i, 0, 0});
      add_element(top, l.pad_base[i], layer_spring(*scene.sleeper_pad), t);
      top = l.pad_base[i];
    }
    SpringDamper lowest = ballast;
    if (scene.ballast_mat) {
      t.push_back({l.mat_top[i], l.mat_top[i], m_i, 0, 0});
      add_element(top, l.mat_top[i], ballast, t);
      top = l.mat_top[i];
      lowest = layer_spring(*scene.ballast_mat);
    }
    if (!scene.has_soil()) t.push_back({top, top, 0, lowest.c, lowest.k});
  }
}

void add_sleepers(const Scene& scene, const DofLayout& l, Triplets& t) {
  if (scene.has_layers()) return add_layered_supports(scene, l, t);
  const auto n = static_cast<std::size_t>(scene.sleeper_count);
  // With a fixed soil the ballast ties each sleeper to the ground.
  const SpringDamper ground = scene.has_soil()
                                  ? SpringDamper{}
                                  : SpringDamper{scene.ballast_stiffness, scene.ballast_damping};
  for (std::size_t i = 0; i < n; ++i)
    t.push_back({l.sleeper[i], l.sleeper[i], scene.sleeper_mass, ground.c, ground.k});
}

void add_soil(const Scene& scene, const DofLayout& l, Triplets& t) {
  const auto n = static_cast<std::size_t>(scene.sleeper_count);
  for (std::size_t i = 0; i < n; ++i) {
    t.push_back({l.soil[i], l.soil[i], scene.soil_mass, scene.soil_damping, scene.soil_stiffness});
    if (i + 1 < n) {
      const double kc = scene.soil_coupling_stiffness, cc = scene.soil_coupling_damping;
      t.push_back({l.soil[i], l.soil[i], 0, cc, kc});
      t.push_back({l.soil[i + 1], l.soil[i + 1], 0, cc, kc});
      t.push_back({l.soil[i + 1], l.soil[i], 0, -cc, -kc});
    }
  }
}

// The linear layers: whole where both ends are held, a spring to held
// values on a side that receives displacements.
void add_layers(const Scene& scene, const ParticipantSpec& participant, const DofLayout& l,
                Triplets& t) {
  const Parts& parts = participant.parts;
  for (int cut = 0; cut < static_cast<int>(cut_kinds().size()); ++cut) {
    const CutKind& kind = cut_kinds()[static_cast<std::size_t>(cut)];
    if (kind.moving) continue;
    if (kind.lower == Component::kSoil && !scene.has_soil()) continue;
    const SpringDamper e = layer_element(scene, cut);
    if (parts.has(kind.upper) && parts.has(kind.lower)) {
      const std::vector<int> up = layer_dofs(l, cut, CutSide::kUpper),
                             lo = layer_dofs(l, cut, CutSide::kLower);
      for (std::size_t i = 0; i < up.size(); ++i) {
        t.push_back({up[i], up[i], 0, e.c, e.k});
        t.push_back({lo[i], lo[i], 0, e.c, e.k});
        t.push_back({lo[i], up[i], 0, -e.c, -e.k});
      }
      continue;
    }
    for (const InterfaceSpec& i : participant.interfaces)
      if (i.cut == cut && !i.receives_force())
        for (int dof : layer_dofs(l, cut, i.side)) t.push_back({dof, dof, 0, e.c, e.k});
  }
}

// M, C and K as band matrices just wide enough for the entries.
void fill_matrices(const Triplets& t, Structure& s) {
  int kd = 0;
  for (const auto& e : t) kd = std::max(kd, std::abs(e.i - e.j));
  s.M = SymmetricBandMatrix(s.layout.size, kd);
  s.C = SymmetricBandMatrix(s.layout.size, kd);
  s.K = SymmetricBandMatrix(s.layout.size, kd);
  for (const auto& e : t) {
    // Entries pushed with i == j are added once; off-diagonal ones once per
    // pair (add() mirrors them).
    s.M.add(e.i, e.j, e.m);
    s.C.add(e.i, e.j, e.c);
    s.K.add(e.i, e.j, e.k);
  }
}

// The wheel/rail contacts, one per wheel, where either of their ends is held.
void add_contacts(const Scene& scene, const ParticipantSpec& participant, Structure& s) {
  const Parts& parts = participant.parts;
  const bool wheel = parts.has(Component::kVehicle), rail = parts.has(Component::kRail);
  if (!wheel && !rail) return;
  std::shared_ptr<const RailProfile> profile;
  if (scene.irregularity.model != "none") {
    // Over the wheels' path, in the scene's frame.
    const auto [a, b] = scene.wheel_path();
    profile = make_profile(scene.irregularity, a, b);
  }
  std::shared_ptr<const WheelFlat> flat;
  if (scene.wheel_flat) flat = std::make_shared<const WheelFlat>(*scene.wheel_flat);
  for (int k = 0; k < scene.wheel_count(); ++k) {
    ContactTerm c;
    c.hertz_constant = scene.hertz_constant;
    c.has_wheel = wheel;
    c.has_rail = rail;
    c.wheel = k;
    c.path = contact_path(scene, k);
    c.excitation.profile = profile;
    c.excitation.origin = scene.rail_start;
    if (flat && scene.wheel_flat->wheel == k) c.excitation.flat = flat;
    for (const InterfaceSpec& i : participant.interfaces)
      if (i.kind().moving && i.receives_force()) c.law = ContactTerm::Law::kPrescribed;
    s.contacts.push_back(std::move(c));
  }
}

}  // namespace

Structure assemble(const Scene& scene, const ParticipantSpec& participant) {
  const Parts& parts = participant.parts;
  Structure s;
  s.layout = make_layout(scene, parts);
  const DofLayout& l = s.layout;
  Triplets t;
  std::optional<VehicleModel> vehicle;
  if (parts.has(Component::kVehicle)) {
    vehicle.emplace(scene.vehicle_model());
    add_vehicle(*vehicle, l, t);
  }
  if (parts.has(Component::kRail)) add_rail(scene, l, t);
  if (parts.has(Component::kSleepers)) add_sleepers(scene, l, t);
  if (parts.has(Component::kSoil)) add_soil(scene, l, t);
  add_layers(scene, participant, l, t);
  fill_matrices(t, s);
  s.load = Vector::Zero(l.size);
  if (vehicle) {
    const Eigen::VectorXd f = vehicle->gravity_load(scene.gravity);
    for (int a = 0; a < vehicle->dofs(); ++a) s.load[l.vehicle[static_cast<std::size_t>(a)]] = f[a];
  }
  add_contacts(scene, participant, s);
  return s;
}

double rail_displacement_at(const ContactPath& path, double t, const std::vector<double>& w,
                            const std::vector<double>& theta) {
  const ContactPoint p = path.at(t);
  const int e = p.element;
  return p.shape[0] * w[e] + p.shape[1] * theta[e] + p.shape[2] * w[e + 1] +
         p.shape[3] * theta[e + 1];
}

std::vector<double> ballast_forces(const Scene& scene, const DofLayout& l, const Vector& u,
                                   const Vector& v, const std::vector<double>* below_u,
                                   const std::vector<double>* below_v) {
  const std::vector<int>& base = l.track_base();
  const SpringDamper e = layer_element(scene, find_cut("ss"));
  std::vector<double> f(base.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    double du = u[base[i]], dv = v[base[i]];
    if (!l.soil.empty()) {
      du -= u[l.soil[i]];
      dv -= v[l.soil[i]];
    } else if (below_u) {
      du -= (*below_u)[i];
      dv -= (*below_v)[i];
    }
    f[i] = e.k * du + e.c * dv;
  }
  return f;
}

}  // namespace railcosim
