#include "vehicle_model.hpp"

#include <cmath>
#include <stdexcept>

#include "hertz.hpp"

namespace railcosim {

namespace {

// The car's wheels relative to its leading wheel: bogie b (front, rear) at
// s_b = +-l_c from the body's centre, its wheelsets at s_w = +-l_t from the
// bogie's.
std::vector<double> car_wheel_offsets(double lc, double lt) {
  std::vector<double> x;
  for (int b = 0; b < 2; ++b)
    for (int w = 0; w < 2; ++w) {
      const double s_b = b == 0 ? lc : -lc, s_w = w == 0 ? lt : -lt;
      x.push_back((s_b + s_w) - (lc + lt));
    }
  return x;
}

}  // namespace

void set_car_keys(VehicleParams& p, const CarParams& c) {
  p.wheelset_mass = c.wheelset_mass;
  p.bogie_mass = c.bogie_mass;
  p.body_mass = c.body_mass;
  p.primary_stiffness = c.primary_stiffness;
  p.primary_damping = c.primary_damping;
  p.secondary_stiffness = c.secondary_stiffness;
  p.secondary_damping = c.secondary_damping;
  p.body_pitch_inertia = c.body_pitch_inertia;
  p.bogie_pitch_inertia = c.bogie_pitch_inertia;
  p.bogie_semi_spacing = c.bogie_semi_spacing;
  p.wheelset_semi_base = c.wheelset_semi_base;
}

VehicleParams car_of_train(const VehicleParams& train, const CarParams& c) {
  VehicleParams p;
  p.type = VehicleType::car;
  p.hertz_constant = train.hertz_constant;
  p.speed = train.speed;
  p.initial_position = train.initial_position;
  set_car_keys(p, c);
  return p;
}

std::vector<double> wheel_offsets(const VehicleParams& p) {
  switch (p.type) {
    case VehicleType::wheel:
    case VehicleType::quarter:
      return {0.0};
    case VehicleType::car:
      return car_wheel_offsets(p.bogie_semi_spacing, p.wheelset_semi_base);
    case VehicleType::train:
      break;
  }
  // Car k's front end at e_k (e_1 = 0; each car's length behind the one
  // before), its leading wheel at e_k - f_k + l_t,k; every offset relative
  // to the first car's leading wheel.
  std::vector<double> x;
  if (p.cars.empty()) return x;
  const double lead = -p.cars.front().front_overhang + p.cars.front().wheelset_semi_base;
  double front_end = 0;
  for (const CarParams& c : p.cars) {
    const double car_lead = (front_end - c.front_overhang + c.wheelset_semi_base) - lead;
    for (double w : car_wheel_offsets(c.bogie_semi_spacing, c.wheelset_semi_base))
      x.push_back(car_lead + w);
    front_end -= c.front_overhang + 2 * c.bogie_semi_spacing + c.rear_overhang;
  }
  return x;
}

const char* to_string(VehicleType t) {
  switch (t) {
    case VehicleType::wheel:
      return "wheel";
    case VehicleType::quarter:
      return "quarter";
    case VehicleType::car:
      return "car";
    case VehicleType::train:
      return "train";
  }
  return "?";
}

VehicleModel::VehicleModel(const VehicleParams& p) : p_(p) {
  if (p.type == VehicleType::train) {
    build_train();
    return;
  }
  std::vector<double> masses;
  switch (p.type) {
    case VehicleType::train:  // built above
      break;
    case VehicleType::wheel:
      names_ = {"wheel"};
      masses = {p.wheel_mass};
      break;
    case VehicleType::quarter:
      names_ = {"body", "bogie", "wheelset"};
      masses = {p.body_mass, p.bogie_mass, p.wheelset_mass};
      break;
    case VehicleType::car:
      names_ = {"body z",      "body phi",   "bogie 1 z",  "bogie 1 phi", "bogie 2 z",
                "bogie 2 phi", "wheelset 1", "wheelset 2", "wheelset 3",  "wheelset 4"};
      masses = {p.body_mass,     p.body_pitch_inertia,  p.bogie_mass,    p.bogie_pitch_inertia,
                p.bogie_mass,    p.bogie_pitch_inertia, p.wheelset_mass, p.wheelset_mass,
                p.wheelset_mass, p.wheelset_mass};
      break;
  }
  const int n = static_cast<int>(masses.size());
  M_ = Eigen::VectorXd::Map(masses.data(), n).asDiagonal();
  C_ = Eigen::MatrixXd::Zero(n, n);
  K_ = Eigen::MatrixXd::Zero(n, n);

  switch (p.type) {
    case VehicleType::train:  // built above
      break;
    case VehicleType::wheel:
      wheels_ = {{0, 0.0}};
      break;
    case VehicleType::quarter:
      add_suspension("secondary", {{0, 1.0}, {1, -1.0}}, p.secondary_stiffness,
                     p.secondary_damping);
      add_suspension("primary", {{1, 1.0}, {2, -1.0}}, p.primary_stiffness, p.primary_damping);
      wheels_ = {{2, 0.0}};
      break;
    case VehicleType::car: {
      const double lc = p.bogie_semi_spacing, lt = p.wheelset_semi_base;
      const std::vector<double> offsets = car_wheel_offsets(lc, lt);
      // Bogie b (0 front, 1 rear) sits at s = +-l_c under the body; its
      // wheelsets at +-l_t from its centre.
      for (int b = 0; b < 2; ++b) {
        const double s_b = b == 0 ? lc : -lc;
        const int zb = 2 + 2 * b, pb = 3 + 2 * b;
        add_suspension(b == 0 ? "secondary front" : "secondary rear",
                       {{0, 1.0}, {1, s_b}, {zb, -1.0}}, p.secondary_stiffness,
                       p.secondary_damping);
        for (int w = 0; w < 2; ++w) {
          const double s_w = w == 0 ? lt : -lt;
          const int wi = 2 * b + w;
          add_suspension("primary " + std::to_string(wi + 1),
                         {{zb, 1.0}, {pb, s_w}, {6 + wi, -1.0}}, p.primary_stiffness,
                         p.primary_damping);
          wheels_.push_back({6 + wi, offsets[static_cast<std::size_t>(wi)]});
        }
      }
      break;
    }
  }
}

void VehicleModel::build_train() {
  if (p_.cars.empty() || p_.cars.size() > static_cast<std::size_t>(kMaxTrainCars))
    throw std::invalid_argument("a train has 1 to " + std::to_string(kMaxTrainCars) +
                                " cars, not " + std::to_string(p_.cars.size()));
  const std::vector<double> offsets = wheel_offsets(p_);
  const int cars = static_cast<int>(p_.cars.size()), n = 10 * cars;
  M_ = Eigen::MatrixXd::Zero(n, n);
  C_ = Eigen::MatrixXd::Zero(n, n);
  K_ = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < cars; ++k) {
    // The car model's own matrices, copied whole onto the diagonal: no
    // term couples two cars.
    const VehicleModel car(car_of_train(p_, p_.cars[static_cast<std::size_t>(k)]));
    const int o = 10 * k;
    M_.block(o, o, 10, 10) = car.mass();
    C_.block(o, o, 10, 10) = car.damping();
    K_.block(o, o, 10, 10) = car.stiffness();
    const std::string prefix = "car " + std::to_string(k + 1) + " ";
    for (const std::string& name : car.dof_names()) names_.push_back(prefix + name);
    for (const Suspension& s : car.suspensions()) {
      Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
      a.segment(o, 10) = s.a;
      susp_.push_back({prefix + s.name, std::move(a), s.stiffness, s.damping});
    }
    for (std::size_t w = 0; w < car.wheels().size(); ++w)
      wheels_.push_back({o + car.wheels()[w].dof, offsets[4 * static_cast<std::size_t>(k) + w]});
  }
}

void VehicleModel::add_suspension(std::string name, std::vector<std::pair<int, double>> terms,
                                  double k, double c) {
  Eigen::VectorXd a = Eigen::VectorXd::Zero(M_.rows());
  for (const auto& [dof, coef] : terms) a(dof) += coef;
  K_ += k * a * a.transpose();
  C_ += c * a * a.transpose();
  susp_.push_back({std::move(name), std::move(a), k, c});
}

Eigen::VectorXd VehicleModel::gravity_load(double g) const {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dofs());
  for (int i = 0; i < dofs(); ++i)
    if (names_[i].find("phi") == std::string::npos) f(i) = M_(i, i) * g;
  return f;
}

double VehicleModel::total_mass() const {
  double m = 0;
  for (int i = 0; i < dofs(); ++i)
    if (names_[i].find("phi") == std::string::npos) m += M_(i, i);
  return m;
}

VehicleStatic VehicleModel::solve_statics(const std::vector<double>& rail_top, double g) const {
  const int nw = static_cast<int>(wheels_.size());
  if (static_cast<int>(rail_top.size()) != nw)
    throw std::invalid_argument("solve_statics: " + std::to_string(rail_top.size()) +
                                " rail-top positions for " + std::to_string(nw) + " wheels");
  // Partition u into the wheels' DOFs W and the rest R (held by springs).
  std::vector<int> rest;
  for (int i = 0; i < dofs(); ++i) {
    bool is_wheel = false;
    for (const auto& w : wheels_) is_wheel = is_wheel || w.dof == i;
    if (!is_wheel) rest.push_back(i);
  }
  const int nr = static_cast<int>(rest.size());
  const Eigen::VectorXd f = gravity_load(g);
  Eigen::MatrixXd Krr(nr, nr), Krw(nr, nw), Kww(nw, nw);
  Eigen::VectorXd fr(nr), fw(nw);
  for (int i = 0; i < nr; ++i) {
    fr(i) = f(rest[i]);
    for (int j = 0; j < nr; ++j) Krr(i, j) = K_(rest[i], rest[j]);
    for (int j = 0; j < nw; ++j) Krw(i, j) = K_(rest[i], wheels_[j].dof);
  }
  for (int i = 0; i < nw; ++i) {
    fw(i) = f(wheels_[i].dof);
    for (int j = 0; j < nw; ++j) Kww(i, j) = K_(wheels_[i].dof, wheels_[j].dof);
  }
  // Given the wheel positions q, the sprung DOFs follow from Krr u_r = f_r -
  // Krw q, and the wheels need the contact forces F(q) = f_w - Kwr u_r - Kww q
  // = F0 - S q (S the Schur complement; zero for a statically determinate
  // vehicle, as all three are). Newton on F(q) = K_H (q - rail_top)^1.5.
  const Eigen::LDLT<Eigen::MatrixXd> lr(Krr);
  const Eigen::MatrixXd A = nr ? Eigen::MatrixXd(lr.solve(Krw)) : Eigen::MatrixXd(0, nw);
  const Eigen::VectorXd ar = nr ? Eigen::VectorXd(lr.solve(fr)) : Eigen::VectorXd(0);
  const Eigen::MatrixXd S = Kww - Krw.transpose() * A;
  const Eigen::VectorXd F0 = fw - Krw.transpose() * ar;
  Eigen::VectorXd top = Eigen::VectorXd::Map(rail_top.data(), nw);
  Eigen::VectorXd q(nw);
  const Eigen::VectorXd F_start = F0 - S * top;
  for (int i = 0; i < nw; ++i) q(i) = top(i) + hertz_penetration(p_.hertz_constant, F_start(i));
  for (int it = 0; it < 50; ++it) {
    Eigen::VectorXd r = F0 - S * q;
    Eigen::MatrixXd J = -S;
    for (int i = 0; i < nw; ++i) {
      const double d = q(i) - top(i);
      if (!(d > 0)) throw std::runtime_error("solve_statics: a wheel would lift off its rail");
      r(i) -= hertz_force(p_.hertz_constant, d);
      J(i, i) -= 1.5 * p_.hertz_constant * std::sqrt(d);
    }
    const Eigen::VectorXd dq = J.partialPivLu().solve(-r);
    q += dq;
    if (dq.cwiseAbs().maxCoeff() <= 1e-15 * (1.0 + q.cwiseAbs().maxCoeff())) break;
  }
  VehicleStatic st;
  st.u = Eigen::VectorXd::Zero(dofs());
  const Eigen::VectorXd ur = ar - A * q;
  for (int i = 0; i < nr; ++i) st.u(rest[i]) = ur(i);
  for (int i = 0; i < nw; ++i) {
    st.u(wheels_[i].dof) = q(i);
    st.penetration.push_back(q(i) - top(i));
    st.contact_force.push_back(hertz_force(p_.hertz_constant, q(i) - top(i)));
  }
  return st;
}

}  // namespace railcosim
