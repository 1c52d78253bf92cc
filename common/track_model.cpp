#include "track_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "hertz.hpp"

namespace railcosim {

DofLayout make_layout(const Scene& scene, Parts parts) {
  DofLayout l;
  l.elements_per_span = scene.elements_per_span;
  l.element_length = scene.element_length();
  int next = 0;
  if (parts.wheel) l.wheel = next++;
  if (parts.sleepers) l.sleeper.assign(scene.sleeper_count, -1);
  if (parts.rail) {
    const int nodes = scene.rail_nodes();
    l.rail_w.resize(nodes);
    l.rail_theta.resize(nodes);
    for (int k = 0; k < nodes; ++k) {
      l.rail_w[k] = next++;
      l.rail_theta[k] = next++;
      const int half = scene.elements_per_span / 2;
      if (parts.sleepers && k % scene.elements_per_span == half) {
        const int i = k / scene.elements_per_span;
        if (i < scene.sleeper_count) l.sleeper[i] = next++;
      }
    }
  } else if (parts.sleepers) {
    for (int i = 0; i < scene.sleeper_count; ++i) l.sleeper[i] = next++;
  }
  l.size = next;
  return l;
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

ContactPath contact_path(const Scene& scene) {
  ContactPath p;
  p.x0 = scene.initial_position;
  p.speed = scene.speed;
  p.element_length = scene.element_length();
  p.elements = scene.rail_nodes() - 1;
  return p;
}

int ContactTerm::entries(double t, const DofLayout& layout, Entry out[5]) const {
  int n = 0;
  if (has_wheel) out[n++] = {layout.wheel, 1.0};
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

}  // namespace

Structure assemble(const Scene& scene, Parts parts, CutPads cut) {
  Structure s;
  s.layout = make_layout(scene, parts);
  const DofLayout& l = s.layout;
  std::vector<Triplet> t;  // lower or upper; symmetric add

  if (parts.wheel) t.push_back({l.wheel, l.wheel, scene.vehicle_mass, 0, 0});

  if (parts.rail) {
    const double L = scene.element_length();
    const Matrix4 ke = beam_stiffness(scene.young_modulus * scene.second_moment, L);
    const Matrix4 me = beam_consistent_mass(scene.density * scene.area, L);
    for (int e = 0; e + 1 < static_cast<int>(l.rail_w.size()); ++e) {
      const int dofs[4] = {l.rail_w[e], l.rail_theta[e], l.rail_w[e + 1], l.rail_theta[e + 1]};
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b <= a; ++b) t.push_back({dofs[a], dofs[b], me(a, b), 0, ke(a, b)});
    }
  }

  for (int i = 0; i < scene.sleeper_count; ++i) {
    const int rail = parts.rail ? l.rail_w[l.pad_node(i)] : -1;
    const int sl = parts.sleepers ? l.sleeper[i] : -1;
    const double kp = scene.pad_stiffness, dp = scene.pad_damping;
    if (sl >= 0) {
      t.push_back({sl, sl, scene.sleeper_mass, scene.ballast_damping, scene.ballast_stiffness});
    }
    if (rail >= 0 && sl >= 0) {
      t.push_back({rail, rail, 0, dp, kp});
      t.push_back({sl, sl, 0, dp, kp});
      t.push_back({sl, rail, 0, -dp, -kp});
    } else if (cut == CutPads::kSprings) {
      const int own = rail >= 0 ? rail : sl;
      if (own >= 0) t.push_back({own, own, 0, dp, kp});
    }
  }

  int kd = 0;
  for (const auto& e : t) kd = std::max(kd, std::abs(e.i - e.j));
  s.M = SymmetricBandMatrix(l.size, kd);
  s.C = SymmetricBandMatrix(l.size, kd);
  s.K = SymmetricBandMatrix(l.size, kd);
  for (const auto& e : t) {
    // Entries pushed with i == j are added once; off-diagonal ones once per
    // pair (add() mirrors them).
    s.M.add(e.i, e.j, e.m);
    s.C.add(e.i, e.j, e.c);
    s.K.add(e.i, e.j, e.k);
  }
  s.load = Vector::Zero(l.size);
  if (parts.wheel) s.load[l.wheel] = scene.load();
  return s;
}

double rail_displacement_at(const ContactPath& path, double t, const std::vector<double>& w,
                            const std::vector<double>& theta) {
  const ContactPoint p = path.at(t);
  const int e = p.element;
  return p.shape[0] * w[e] + p.shape[1] * theta[e] + p.shape[2] * w[e + 1] +
         p.shape[3] * theta[e + 1];
}

StaticState solve_statics(const Scene& scene) {
  // The wheel is carried by the contact alone, so F = m_tot g exactly; the
  // track (rail, pads, sleepers, ballast) is linear: K w = N(x_0)^T F.
  Structure track = assemble(scene, {false, true, true}, CutPads::kNone);
  const DofLayout& l = track.layout;
  const ContactPath path = contact_path(scene);
  const ContactPoint p = path.at(0.0);
  const double F = scene.load();
  Vector f = Vector::Zero(l.size);
  const int e = p.element;
  f[l.rail_w[e]] += p.shape[0] * F;
  f[l.rail_theta[e]] += p.shape[1] * F;
  f[l.rail_w[e + 1]] += p.shape[2] * F;
  f[l.rail_theta[e + 1]] += p.shape[3] * F;
  BandCholesky(track.K).solve_in_place(f);

  StaticState st;
  st.contact_force = F;
  for (std::size_t k = 0; k < l.rail_w.size(); ++k) {
    st.rail_w.push_back(f[l.rail_w[k]]);
    st.rail_theta.push_back(f[l.rail_theta[k]]);
  }
  for (int dof : l.sleeper) st.sleeper.push_back(f[dof]);
  st.wheel = rail_displacement_at(path, 0.0, st.rail_w, st.rail_theta) +
             hertz_penetration(scene.hertz_constant, F);
  return st;
}

}  // namespace railcosim
