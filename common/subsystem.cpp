#include "subsystem.hpp"

#include <cmath>

namespace railcosim {
namespace {

Parts parts_of(Split split, Side side) {
  if (split == Split::kWheelRail)
    return side == Side::kS1 ? Parts{true, false, false} : Parts{false, true, true};
  return side == Side::kS1 ? Parts{true, true, false} : Parts{false, false, true};
}

// The railpad appears as a spring/damper to held values on every side that
// receives a displacement; S2 of an X-T rail/sleepers cut receives the force.
CutPads cut_pads_of(const SubsystemConfig& c) {
  if (c.split != Split::kRailSleepers) return CutPads::kNone;
  if (c.side == Side::kS2 && c.coupling == Coupling::kXT) return CutPads::kNone;
  return CutPads::kSprings;
}

}  // namespace

Subsystem::Subsystem(const Scene& scene, const SubsystemConfig& config)
    : scene_(scene),
      config_(config),
      points_(config.split == Split::kWheelRail ? 1 : scene.sleeper_count),
      sys_(assemble(scene, parts_of(config.split, config.side), cut_pads_of(config))) {
  const Parts parts = parts_of(config.split, config.side);
  if (config.split == Split::kWheelRail || parts.wheel) {
    ContactTerm c;
    c.hertz_constant = scene.hertz_constant;
    c.has_wheel = parts.wheel;
    c.has_rail = parts.rail;
    c.path = contact_path(scene);
    if (config.side == Side::kS2 && config.coupling == Coupling::kXT)
      c.law = ContactTerm::Law::kPrescribed;
    sys_.contact = c;
  }
  base_load_ = sys_.load;
  newmark_ = std::make_unique<Newmark>(sys_, config.macro_step, config.tolerance, 0,
                                       config.max_micro_steps);
}

std::string Subsystem::name() const {
  return to_string(config_.side) + " of " + to_string(config_.split) + "-" +
         to_string(config_.coupling);
}

void Subsystem::require(bool ok, const std::string& call, const std::string& why) const {
  if (!ok) throw CallOrderError(name() + ": " + call + " rejected: " + why);
}

StepResult Subsystem::initialize() {
  require(phase_ == Phase::kCreated, "initialize()", "initialize() may only be called once");
  // Start from the static equilibrium of the whole model, and hold the other
  // side's static values as the first inputs.
  const StaticState st = solve_statics(scene_);
  const DofLayout& l = sys_.layout;
  Vector u = Vector::Zero(l.size);
  if (l.wheel >= 0) u[l.wheel] = st.wheel;
  for (std::size_t k = 0; k < l.rail_w.size(); ++k) {
    u[l.rail_w[k]] = st.rail_w[k];
    u[l.rail_theta[k]] = st.rail_theta[k];
  }
  for (std::size_t i = 0; i < l.sleeper.size(); ++i) u[l.sleeper[i]] = st.sleeper[i];
  newmark_->state().u = u;

  CouplingData in;
  const auto N = static_cast<std::size_t>(points_);
  const bool xt = config_.coupling == Coupling::kXT;
  const ContactPath path = contact_path(scene_);
  if (config_.split == Split::kWheelRail) {
    if (config_.side == Side::kS1)
      in.displacement = {rail_displacement_at(path, 0.0, st.rail_w, st.rail_theta)};
    else if (xt)
      in.force = {st.contact_force};
    else
      in.displacement = {st.wheel};
  } else {
    if (config_.side == Side::kS1) {
      in.displacement = st.sleeper;
      in.velocity.assign(N, 0.0);
    } else if (xt) {
      for (std::size_t i = 0; i < N; ++i)
        in.force.push_back(scene_.pad_stiffness *
                           (st.rail_w[l.pad_node(static_cast<int>(i))] - st.sleeper[i]));
    } else {
      for (std::size_t i = 0; i < N; ++i)
        in.displacement.push_back(st.rail_w[l.pad_node(static_cast<int>(i))]);
      in.velocity.assign(N, 0.0);
    }
  }
  apply_inputs(in);
  newmark_->set_state(u, Vector::Zero(l.size), 0.0);
  phase_ = Phase::kAwaitingInputs;
  return report();
}

void Subsystem::check_inputs(const CouplingData& in) const {
  const auto N = static_cast<std::size_t>(points_);
  const bool wants_force = config_.side == Side::kS2 && config_.coupling == Coupling::kXT;
  const bool wants_velocity = config_.split == Split::kRailSleepers && !wants_force;
  auto expect = [&](const std::vector<double>& v, bool wanted, const char* what) {
    const std::size_t size = wanted ? N : 0;
    if (v.size() != size)
      throw BadInputError(name() + ": set_inputs() rejected: expected " + std::to_string(size) +
                          " " + what + " value(s), got " + std::to_string(v.size()));
    for (double x : v)
      if (!std::isfinite(x))
        throw BadInputError(name() + ": set_inputs() rejected: non-finite " + what + " value");
  };
  expect(in.displacement, !wants_force, "displacement");
  expect(in.velocity, wants_velocity, "velocity");
  expect(in.force, wants_force, "force");
}

void Subsystem::apply_inputs(const CouplingData& in) {
  check_inputs(in);
  held_ = in;
  const DofLayout& l = sys_.layout;
  sys_.load = base_load_;
  if (config_.split == Split::kWheelRail) {
    ContactTerm& c = *sys_.contact;
    if (config_.side == Side::kS1)
      c.held_rail = in.displacement[0];
    else if (config_.coupling == Coupling::kXT)
      c.prescribed_force = in.force[0];
    else
      c.held_wheel = in.displacement[0];
  } else {
    const double kp = scene_.pad_stiffness, dp = scene_.pad_damping;
    for (int i = 0; i < points_; ++i) {
      const int dof = config_.side == Side::kS1 ? l.rail_w[l.pad_node(i)] : l.sleeper[i];
      sys_.load[dof] +=
          in.force.empty() ? kp * in.displacement[i] + dp * in.velocity[i] : in.force[i];
    }
  }
}

void Subsystem::set_inputs(long n, const CouplingData& inputs) {
  require(phase_ == Phase::kAwaitingInputs || phase_ == Phase::kInputsSet,
          "set_inputs(" + std::to_string(n) + ")",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  require(n == next_step_, "set_inputs(" + std::to_string(n) + ")",
          "the subsystem is at macro step " + std::to_string(next_step_));
  apply_inputs(inputs);
  // The held inputs changed the forces: restart from a consistent acceleration.
  newmark_->update_acceleration(time(n));
  phase_ = Phase::kInputsSet;
}

CouplingData Subsystem::outputs() {
  require(phase_ == Phase::kAwaitingInputs || phase_ == Phase::kInputsSet, "outputs()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  return compute_outputs();
}

CouplingData Subsystem::compute_outputs() const {
  const Vector& u = newmark_->state().u;
  const Vector& v = newmark_->state().v;
  const DofLayout& l = sys_.layout;
  const double t = time(next_step_);
  const bool xt = config_.coupling == Coupling::kXT;
  CouplingData out;
  if (config_.split == Split::kWheelRail) {
    if (config_.side == Side::kS1) {
      if (xt)
        out.force = {newmark_->contact_force(u, t)};
      else
        out.displacement = {u[l.wheel]};
    } else {
      const ContactPoint p = sys_.contact->path.at(t);
      const int e = p.element;
      out.displacement = {p.shape[0] * u[l.rail_w[e]] + p.shape[1] * u[l.rail_theta[e]] +
                          p.shape[2] * u[l.rail_w[e + 1]] + p.shape[3] * u[l.rail_theta[e + 1]]};
    }
    return out;
  }
  const double kp = scene_.pad_stiffness, dp = scene_.pad_damping;
  for (int i = 0; i < points_; ++i) {
    const int dof = config_.side == Side::kS1 ? l.rail_w[l.pad_node(i)] : l.sleeper[i];
    if (config_.side == Side::kS1 && xt) {
      out.force.push_back(kp * (u[dof] - held_.displacement[i]) +
                          dp * (v[dof] - held_.velocity[i]));
    } else {
      out.displacement.push_back(u[dof]);
      out.velocity.push_back(v[dof]);
    }
  }
  return out;
}

void Subsystem::start_step(long n) {
  require(phase_ != Phase::kCreated, "start_step(" + std::to_string(n) + ")",
          "initialize() must come first");
  require(phase_ != Phase::kStepping, "start_step(" + std::to_string(n) + ")",
          "the previous step has not been finished");
  require(phase_ == Phase::kInputsSet, "start_step(" + std::to_string(n) + ")",
          "set_inputs() must come first for every macro step");
  require(n == next_step_, "start_step(" + std::to_string(n) + ")",
          "the subsystem is at macro step " + std::to_string(next_step_));
  phase_ = Phase::kStepping;
  try {
    newmark_->advance(time(n), time(n + 1));
  } catch (const StepFailure&) {
    phase_ = Phase::kAwaitingInputs;  // results() still answers, with the state reached
    throw;
  }
  ++next_step_;
}

StepResult Subsystem::finish_step() {
  require(phase_ == Phase::kStepping, "finish_step()", "no step was started");
  phase_ = Phase::kAwaitingInputs;
  return report();
}

StepResult Subsystem::report() const {
  const DofLayout& l = sys_.layout;
  const NewmarkState& s = newmark_->state();
  StepResult r;
  r.finite = s.u.allFinite() && s.v.allFinite();
  double m = 0;
  if (l.wheel >= 0) m = std::abs(s.u[l.wheel]);
  for (int dof : l.rail_w) m = std::max(m, std::abs(s.u[dof]));
  for (int dof : l.sleeper) m = std::max(m, std::abs(s.u[dof]));
  r.max_abs_displacement = m;
  if (l.wheel >= 0) {
    const double t = time(next_step_);
    r.row = HistoryRow{t, s.u[l.wheel], newmark_->contact_force(s.u, t)};
  }
  r.outputs = compute_outputs();
  return r;
}

ParticipantResults Subsystem::results() {
  require(phase_ != Phase::kCreated && phase_ != Phase::kStepping, "results()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  ParticipantResults r;
  for (int dof : sys_.layout.rail_w) r.rail_deflection.push_back(newmark_->state().u[dof]);
  r.micro_steps = newmark_->state().micro_steps;
  return r;
}

namespace {

void put(std::vector<double>& out, const std::vector<double>& v) {
  out.push_back(static_cast<double>(v.size()));
  out.insert(out.end(), v.begin(), v.end());
}
void put(std::vector<double>& out, const Vector& v) {
  out.push_back(static_cast<double>(v.size()));
  out.insert(out.end(), v.data(), v.data() + v.size());
}

class Cursor {
 public:
  Cursor(const std::vector<double>& v, const std::string& who) : v_(v), who_(who) {}
  double next() {
    if (i_ >= v_.size()) throw BadInputError(who_ + ": restore() rejected: the state is truncated");
    return v_[i_++];
  }
  std::size_t count(std::size_t limit) {
    const double c = next();
    if (!(c >= 0 && c <= static_cast<double>(limit)))
      throw BadInputError(who_ + ": restore() rejected: the state does not fit this subsystem");
    return static_cast<std::size_t>(c);
  }
  std::vector<double> vec(std::size_t limit) {
    const std::size_t n = count(limit);
    std::vector<double> out(n);
    for (auto& x : out) x = next();
    return out;
  }
  bool done() const { return i_ == v_.size(); }

 private:
  const std::vector<double>& v_;
  std::string who_;
  std::size_t i_ = 0;
};

}  // namespace

ParticipantState Subsystem::save() {
  require(phase_ != Phase::kCreated && phase_ != Phase::kStepping, "save()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  const NewmarkState& s = newmark_->state();
  ParticipantState st;
  auto& o = st.values;
  o.push_back(static_cast<double>(next_step_));
  o.push_back(phase_ == Phase::kInputsSet ? 1.0 : 0.0);
  o.push_back(static_cast<double>(s.level));
  o.push_back(static_cast<double>(s.micro_steps));
  o.push_back(static_cast<double>(s.rejected_steps));
  o.push_back(s.contact_force);
  put(o, s.u);
  put(o, s.v);
  put(o, s.a);
  put(o, held_.displacement);
  put(o, held_.velocity);
  put(o, held_.force);
  return st;
}

void Subsystem::restore(const ParticipantState& state) {
  require(phase_ != Phase::kCreated && phase_ != Phase::kStepping, "restore()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  Cursor c(state.values, name());
  const long step = static_cast<long>(c.next());
  const bool inputs_set = c.next() != 0.0;
  const int level = static_cast<int>(c.next());
  const long micro = static_cast<long>(c.next());
  const long rejected = static_cast<long>(c.next());
  const double force = c.next();
  const auto n = static_cast<std::size_t>(sys_.layout.size);
  const auto N = static_cast<std::size_t>(points_);
  const std::vector<double> u = c.vec(n), v = c.vec(n), a = c.vec(n);
  CouplingData held{c.vec(N), c.vec(N), c.vec(N)};
  if (!c.done() || u.size() != n || v.size() != n || a.size() != n || step < 0 || level < 0 ||
      level > Newmark::kMaxLevel)
    throw BadInputError(name() + ": restore() rejected: the state does not fit this subsystem");
  apply_inputs(held);
  NewmarkState& s = newmark_->state();
  s.u = Eigen::Map<const Vector>(u.data(), static_cast<Eigen::Index>(n));
  s.v = Eigen::Map<const Vector>(v.data(), static_cast<Eigen::Index>(n));
  s.a = Eigen::Map<const Vector>(a.data(), static_cast<Eigen::Index>(n));
  s.level = level;
  s.micro_steps = micro;
  s.rejected_steps = rejected;
  s.contact_force = force;
  next_step_ = step;
  phase_ = inputs_set ? Phase::kInputsSet : Phase::kAwaitingInputs;
}

}  // namespace railcosim
