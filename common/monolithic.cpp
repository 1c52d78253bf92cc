#include "monolithic.hpp"

namespace railcosim {

MonolithicModel::MonolithicModel(const Scene& scene, double output_step, double tolerance)
    : sys_(assemble(scene, {true, true, true}, CutPads::kNone)),
      dt_(output_step),
      newmark_(sys_, output_step, tolerance) {
  ContactTerm c;
  c.law = ContactTerm::Law::kHertz;
  c.hertz_constant = scene.hertz_constant;
  c.has_wheel = true;
  c.has_rail = true;
  c.path = contact_path(scene);
  sys_.contact = c;

  const StaticState st = solve_statics(scene);
  const DofLayout& l = sys_.layout;
  Vector u = Vector::Zero(l.size);
  u[l.wheel] = st.wheel;
  for (std::size_t k = 0; k < l.rail_w.size(); ++k) {
    u[l.rail_w[k]] = st.rail_w[k];
    u[l.rail_theta[k]] = st.rail_theta[k];
  }
  for (std::size_t i = 0; i < l.sleeper.size(); ++i) u[l.sleeper[i]] = st.sleeper[i];
  newmark_.set_state(u, Vector::Zero(l.size), 0.0);
}

void MonolithicModel::advance(long n) {
  newmark_.advance(static_cast<double>(n) * dt_, static_cast<double>(n + 1) * dt_);
}

HistoryRow MonolithicModel::history_row(long n) const {
  return {static_cast<double>(n) * dt_, newmark_.state().u[sys_.layout.wheel],
          newmark_.state().contact_force};
}

double MonolithicModel::rail_under_wheel(double t) const {
  const Vector& u = newmark_.state().u;
  const DofLayout& l = sys_.layout;
  std::vector<double> w, theta;
  for (std::size_t k = 0; k < l.rail_w.size(); ++k) {
    w.push_back(u[l.rail_w[k]]);
    theta.push_back(u[l.rail_theta[k]]);
  }
  return rail_displacement_at(sys_.contact->path, t, w, theta);
}

std::vector<double> MonolithicModel::rail_deflection() const {
  std::vector<double> w;
  w.reserve(sys_.layout.rail_w.size());
  for (int dof : sys_.layout.rail_w) w.push_back(newmark_.state().u[dof]);
  return w;
}

}  // namespace railcosim
