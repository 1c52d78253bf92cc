#include "monolithic.hpp"

#include <algorithm>
#include <cmath>

#include "statics.hpp"
#include "subsystem.hpp"

namespace railcosim {

namespace {

ParticipantSpec whole_model(const Scene& scene) {
  ParticipantSpec p;
  p.role = "monolithic";
  p.parts = Parts::all(scene);
  return p;
}

}  // namespace

MonolithicModel::MonolithicModel(const Scene& scene, double output_step, double tolerance)
    : scene_(scene),
      sys_(assemble(scene, whole_model(scene))),
      dt_(output_step),
      newmark_(sys_, output_step, tolerance, 0, Newmark::kMaxStepsPerInterval, scene.micro_steps) {
  const Vector u = solve_static(sys_, Vector::Zero(sys_.layout.size), 0.0);
  newmark_.set_state(u, Vector::Zero(sys_.layout.size), 0.0);
}

void MonolithicModel::advance(long n) {
  newmark_.advance(static_cast<double>(n) * dt_, static_cast<double>(n + 1) * dt_);
}

HistoryRow MonolithicModel::history_row(long n) const {
  const Vector& u = newmark_.state().u;
  const double t = static_cast<double>(n) * dt_;
  HistoryRow row{t, u[sys_.layout.wheel], newmark_.state().contact_force, {}};
  if (sys_.contacts.size() > 1)
    for (std::size_t k = 0; k < sys_.contacts.size(); ++k)
      row.extra.push_back(newmark_.contact_force(u, t, k));
  if (scene_.ballast_forces)
    for (double f : ballast_forces(scene_, sys_.layout, u, newmark_.state().v, nullptr, nullptr))
      row.extra.push_back(f);
  if (!sys_.layout.soil.empty()) {
    double peak = 0;
    for (int dof : sys_.layout.soil) peak = std::max(peak, std::abs(u[dof]));
    row.extra.push_back(peak);
  }
  return row;
}

std::vector<std::string> MonolithicModel::extra_channels() const {
  std::vector<std::string> names = channels_of(scene_, Parts::all(scene_)).history;
  names.erase(names.begin(), names.begin() + 2);  // wheel_m, contact_force_N
  return names;
}

std::vector<double> MonolithicModel::soil_deflection() const {
  std::vector<double> s;
  for (int dof : sys_.layout.soil) s.push_back(newmark_.state().u[dof]);
  return s;
}

double MonolithicModel::rail_under_wheel(double t) const {
  const Vector& u = newmark_.state().u;
  const DofLayout& l = sys_.layout;
  std::vector<double> w, theta;
  for (std::size_t k = 0; k < l.rail_w.size(); ++k) {
    w.push_back(u[l.rail_w[k]]);
    theta.push_back(u[l.rail_theta[k]]);
  }
  return rail_displacement_at(sys_.contacts.front().path, t, w, theta);
}

std::vector<double> MonolithicModel::rail_deflection() const {
  std::vector<double> w;
  w.reserve(sys_.layout.rail_w.size());
  for (int dof : sys_.layout.rail_w) w.push_back(newmark_.state().u[dof]);
  return w;
}

}  // namespace railcosim
