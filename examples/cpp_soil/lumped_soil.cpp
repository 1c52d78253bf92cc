#include "lumped_soil.hpp"

#include <cmath>
#include <utility>
#include <vector>

using Eigen::VectorXd;
using railcosim::BadInputError;
using railcosim::CallOrderError;
using railcosim::CouplingData;
using railcosim::InterfaceData;

namespace {

std::vector<double> to_std(const VectorXd& v) {
  return {v.data(), v.data() + v.size()};
}

}  // namespace

LumpedSoil::LumpedSoil(const railcosim::ParticipantSetup& setup) {
  // Its own model: the table [soil] of --config (or of the master's scene
  // when its soil is "external"); a missing key is BAD_REQUEST naming it.
  const railcosim::OwnConfig& own = setup.config;
  const double mass = own.number("mass"), stiffness = own.number("stiffness"),
               damping = own.number("damping"), kc = own.number("coupling_stiffness"),
               cc = own.number("coupling_damping");
  const auto& interfaces = setup.interfaces;
  if (interfaces.size() != 1 || interfaces[0].cut != "ss" || interfaces[0].upper)
    throw railcosim::BadInterfaceError(
        "this soil serves only the lower side of the ss cut (the ballast), one interface");
  const railcosim::Interface& ss = interfaces[0];
  using Q = railcosim::Quantity;
  const std::vector<Q> motion{Q::kDisplacement, Q::kVelocity};
  if ((ss.receives != motion && !ss.receives_force()) || ss.sends != motion)
    throw railcosim::BadInterfaceError(
        "interface " + ss.describe() +
        ": it receives displacement and velocity, or force, and sends displacement and velocity");
  if (setup.run.micro_steps <= 0)
    throw railcosim::BadRequestError(
        "this soil integrates with a fixed number of micro steps: set simulation.micro_steps");
  n_ = static_cast<long>(ss.n());
  receives_force_ = ss.receives_force();
  kb_ = ss.stiffness;  // the ballast, per coupling point
  cb_ = ss.damping;
  H_ = setup.run.macro_step;
  m_ = setup.run.micro_steps;
  carry_ = setup.run.carry_acceleration;
  h_ = H_ / m_;
  M_ = Eigen::MatrixXd::Identity(n_, n_) * mass;
  K_ = Eigen::MatrixXd::Identity(n_, n_) * stiffness;
  C_ = Eigen::MatrixXd::Identity(n_, n_) * damping;
  for (long i = 0; i + 1 < n_; ++i)
    for (auto [A, c] : {std::pair{&K_, kc}, std::pair{&C_, cc}}) {
      (*A)(i, i) += c;
      (*A)(i + 1, i + 1) += c;
      (*A)(i, i + 1) -= c;
      (*A)(i + 1, i) -= c;
    }
  if (!receives_force_) {  // the ballast's spring and damper to the held sleeper values
    K_.diagonal().array() += kb_;
    C_.diagonal().array() += cb_;
  }
  const double c0 = 1.0 / (0.25 * h_ * h_), c1 = 0.5 / (0.25 * h_);
  Keff_.compute(K_ + c1 * C_ + c0 * M_);
  Kstat_.compute(K_);
  u_ = v_ = a_ = load_ = rate_ = VectorXd::Zero(n_);
}

VectorXd LumpedSoil::load_of(const CouplingData& in) const {
  const auto count = static_cast<std::size_t>(n_);
  if (in.size() != 1) throw BadInputError("soil: expected the inputs of one interface");
  const InterfaceData& d = in[0];
  const bool fits = receives_force_ ? d.force.size() == count && d.displacement.empty()
                                    : d.displacement.size() == count && d.velocity.size() == count;
  if (!fits) throw BadInputError("soil: the inputs do not fit " + std::to_string(n_) + " points");
  for (const auto* a : {&d.displacement, &d.velocity, &d.force})
    for (double x : *a)
      if (!std::isfinite(x)) throw BadInputError("soil: an input is not finite");
  if (receives_force_) return Eigen::Map<const VectorXd>(d.force.data(), n_);
  return kb_ * Eigen::Map<const VectorXd>(d.displacement.data(), n_) +
         cb_ * Eigen::Map<const VectorXd>(d.velocity.data(), n_);
}

void LumpedSoil::restart() {
  a_ = (load_ - C_ * v_ - K_ * u_) / M_(0, 0);
}

CouplingData LumpedSoil::statics(const CouplingData& inputs) {
  if (micro_steps_ > 0 || next_ >= 0) throw CallOrderError("soil: statics() after initialize()");
  load_ = load_of(inputs);
  rate_.setZero();
  u_ = Kstat_.solve(load_);
  v_.setZero();
  restart();
  return outputs();
}

railcosim::StepResult LumpedSoil::initialize(const CouplingData& inputs) {
  statics(inputs);
  next_ = 0;
  return report();
}

void LumpedSoil::set_inputs(long n, const CouplingData& inputs) {
  if (n != next_)
    throw CallOrderError("soil: inputs for step " + std::to_string(n) + ", at step " +
                         std::to_string(next_));
  waves_.clear();
  load_ = load_of(inputs);
  rate_.setZero();
  if (!carry_) restart();
}

void LumpedSoil::set_inputs(long n, const CouplingData& start, const CouplingData& end) {
  const VectorXd last = load_of(end);
  set_inputs(n, start);
  rate_ = (last - load_) / H_;
  if (!carry_) restart();
}

void LumpedSoil::set_input_waveforms(long n, const railcosim::InputWaveforms& inputs) {
  const auto count = static_cast<std::size_t>(n_);
  if (inputs.size() != 1 || inputs[0].width() != (receives_force_ ? count : 2 * count))
    throw BadInputError("soil: the input waveforms do not fit " + std::to_string(n_) + " points");
  // The ends of the window as a ramp (what save() keeps), then the waveform.
  InterfaceData shape;
  (receives_force_ ? shape.force : shape.displacement).resize(count);
  if (!receives_force_) shape.velocity.resize(count);
  const double t0 = static_cast<double>(n) * H_;
  set_inputs(n, {railcosim::unpack_values(inputs[0].at(t0), shape)},
             {railcosim::unpack_values(inputs[0].at(t0 + H_), shape)});
  waves_ = inputs;
}

VectorXd LumpedSoil::load_at(double t) const {
  const std::vector<double> v = waves_[0].at(t);
  const Eigen::Map<const VectorXd> all(v.data(), static_cast<Eigen::Index>(v.size()));
  if (receives_force_) return all;
  return kb_ * all.head(n_) + cb_ * all.tail(n_);
}

CouplingData LumpedSoil::outputs() {
  return {InterfaceData{to_std(u_), to_std(v_), {}}};
}

void LumpedSoil::start_step(long n) {
  if (n != next_)
    throw CallOrderError("soil: step " + std::to_string(n) + " asked, at step " +
                         std::to_string(next_));
  const double c0 = 1.0 / (0.25 * h_ * h_), c1 = 0.5 / (0.25 * h_);
  const double t0 = static_cast<double>(n) * H_;
  samples_.clear();
  if (record_) samples_.push_back({.t = t0, .outputs = outputs()});
  for (int k = 0; k < m_; ++k) {
    const VectorXd pu = u_ + h_ * v_ + (h_ * h_ * 0.25) * a_;
    const VectorXd pv = v_ + (h_ * 0.5) * a_;
    // The micro step's end, where the load is taken.
    const double t = k + 1 == m_ ? static_cast<double>(n + 1) * H_ : t0 + (k + 1) * h_;
    const VectorXd load = waves_.empty() ? VectorXd(load_ + rate_ * ((k + 1) * h_)) : load_at(t);
    const VectorXd u = Keff_.solve(load + M_ * (c0 * pu) + C_ * (c1 * pu - pv));
    a_ = c0 * (u - pu);
    v_ = pv + (0.5 * h_) * a_;
    u_ = u;
    ++micro_steps_;
    if (record_) samples_.push_back({.t = t, .outputs = outputs()});
  }
  ++next_;
}

railcosim::StepResult LumpedSoil::finish_step() {
  return report();
}

railcosim::StepResult LumpedSoil::report() const {
  railcosim::StepResult r;
  r.outputs = {InterfaceData{to_std(u_), to_std(v_), {}}};
  r.max_abs_displacement = u_.cwiseAbs().maxCoeff();
  r.finite = u_.allFinite() && v_.allFinite();
  r.history = {r.max_abs_displacement};  // soil_peak_m
  return r;
}

railcosim::ParticipantResults LumpedSoil::results() {
  return {{to_std(u_)}, micro_steps_};
}

railcosim::ParticipantState LumpedSoil::save() {
  railcosim::ParticipantState s{{static_cast<double>(next_), static_cast<double>(micro_steps_)}};
  for (const VectorXd* x : {&u_, &v_, &a_, &load_, &rate_})
    s.values.insert(s.values.end(), x->data(), x->data() + x->size());
  return s;
}

void LumpedSoil::restore(const railcosim::ParticipantState& s) {
  if (s.values.size() != static_cast<std::size_t>(2 + 5 * n_) || !(s.values[0] >= 0) ||
      !(s.values[1] >= 0) || s.values[0] > 1e15 || s.values[1] > 1e15)
    throw BadInputError("soil: the state does not fit this participant");
  waves_.clear();  // the state holds the ramp between the window's ends
  next_ = static_cast<long>(s.values[0]);
  micro_steps_ = static_cast<long>(s.values[1]);
  const double* p = s.values.data() + 2;
  for (VectorXd* x : {&u_, &v_, &a_, &load_, &rate_}) {
    *x = Eigen::Map<const VectorXd>(p, n_);
    p += n_;
  }
}
