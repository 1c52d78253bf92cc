#include "subsystem.hpp"

#include <cmath>
#include <optional>

#include "statics.hpp"

namespace railcosim {

SubsystemConfig subsystem_config(const Scene& scene, const ParticipantSpec& p, double macro_step,
                                 double tolerance) {
  SubsystemConfig c;
  c.participant = p;
  c.macro_step = macro_step;
  c.tolerance = tolerance;
  c.micro_steps = scene.micro_steps;
  c.carry_acceleration = scene.restart == "carry";
  return c;
}

int interface_points(const Scene& scene, const InterfaceSpec& i) {
  return i.kind().moving ? scene.wheel_count() : scene.sleeper_count;
}

Channels channels_of(const Scene& scene, const Parts& parts) {
  Channels c;
  if (parts.has(Component::kVehicle)) {
    c.history = {"wheel_m", "contact_force_N"};
    if (scene.wheel_count() > 1)
      for (int k = 1; k <= scene.wheel_count(); ++k)
        c.history.push_back("force_w" + std::to_string(k) + "_N");
  }
  if (parts.has(Component::kSleepers) && scene.ballast_forces)
    for (int i = 1; i <= scene.sleeper_count; ++i)
      c.history.push_back("ballast_force_" + std::to_string(i) + "_N");
  if (parts.has(Component::kSoil)) c.history.push_back("soil_peak_m");
  if (parts.has(Component::kRail)) c.results.push_back("rail_w_m");
  if (parts.has(Component::kSoil)) c.results.push_back("soil_m");
  return c;
}

Subsystem::Subsystem(const Scene& scene, const SubsystemConfig& config)
    : scene_(scene), config_(config), sys_(assemble(scene, config.participant)) {
  for (const InterfaceSpec& i : config_.participant.interfaces) {
    points_.push_back(interface_points(scene, i));
    dofs_.push_back(layer_dofs(sys_.layout, i.cut, i.side));
    elements_.push_back(layer_element(scene, i.cut));
  }
  base_load_ = sys_.load;
  static_u_ = Vector::Zero(sys_.layout.size);
  newmark_ = std::make_unique<Newmark>(sys_, config.macro_step, config.tolerance, 0,
                                       config.max_micro_steps, config.micro_steps);
}

std::string Subsystem::name() const {
  std::string cuts;
  for (const InterfaceSpec& i : config_.participant.interfaces)
    cuts += std::string(cuts.empty() ? "" : ", ") + i.kind().name + "-" + to_string(i.coupling) +
            (i.side == CutSide::kUpper ? " upper" : " lower");
  return config_.participant.role + " (" + cuts + ")";
}

void Subsystem::require(bool ok, const std::string& call, const std::string& why) const {
  if (!ok) throw CallOrderError(name() + ": " + call + " rejected: " + why);
}

CouplingData Subsystem::statics(const CouplingData& inputs) {
  require(phase_ == Phase::kCreated, "statics()", "the statics come before initialize()");
  apply_inputs(inputs, nullptr, 0.0);
  static_u_ = solve_static(sys_, static_u_, 0.0);
  return compute_outputs(static_u_, Vector::Zero(sys_.layout.size), 0.0, held_);
}

StepResult Subsystem::initialize(const CouplingData& inputs) {
  require(phase_ == Phase::kCreated, "initialize()", "initialize() may only be called once");
  statics(inputs);
  newmark_->set_state(static_u_, Vector::Zero(sys_.layout.size), 0.0);
  phase_ = Phase::kAwaitingInputs;
  return report();
}

std::string Subsystem::input_fault(std::size_t j, const InterfaceData& data, bool any_value) const {
  const auto& ifs = config_.participant.interfaces;
  if (j >= ifs.size()) return "interface " + std::to_string(j) + " does not exist";
  bool want[3] = {false, false, false};
  for (Quantity q : ifs[j].receives()) want[static_cast<int>(q)] = true;
  const std::vector<double>* got[3] = {&data.displacement, &data.velocity, &data.force};
  for (int q = 0; q < 3; ++q) {
    const std::size_t size = want[q] ? static_cast<std::size_t>(points_[j]) : 0;
    const std::string what =
        std::string(ifs[j].kind().name) + " " + to_string(static_cast<Quantity>(q));
    if (got[q]->size() != size)
      return "expected " + std::to_string(size) + " " + what + " value(s), got " +
             std::to_string(got[q]->size());
    for (double x : *got[q])
      if (!any_value && !std::isfinite(x)) return "non-finite " + what + " value";
  }
  return "";
}

void Subsystem::check_inputs(const CouplingData& in) const {
  const auto& ifs = config_.participant.interfaces;
  if (in.size() != ifs.size())
    throw BadInputError(name() + ": inputs rejected: expected values for " +
                        std::to_string(ifs.size()) + " interface(s), got " +
                        std::to_string(in.size()));
  for (std::size_t j = 0; j < ifs.size(); ++j)
    if (const std::string why = input_fault(j, in[j]); !why.empty())
      throw BadInputError(name() + ": inputs rejected: " + why);
}

Subsystem::Loads Subsystem::loads_of(const CouplingData& in) const {
  Loads r;
  r.load = base_load_;
  const std::size_t contacts = sys_.contacts.size();
  r.wheel.assign(contacts, 0.0);
  r.rail.assign(contacts, 0.0);
  r.force.assign(contacts, 0.0);
  const auto& ifs = config_.participant.interfaces;
  for (std::size_t j = 0; j < ifs.size(); ++j) {
    const InterfaceSpec& i = ifs[j];
    if (i.kind().moving) {
      if (i.side == CutSide::kUpper)
        r.rail = in[j].displacement;
      else if (i.receives_force())
        r.force = in[j].force;
      else
        r.wheel = in[j].displacement;
      continue;
    }
    const SpringDamper e = elements_[j];
    for (std::size_t p = 0; p < dofs_[j].size(); ++p)
      r.load[dofs_[j][p]] += i.receives_force()
                                 ? in[j].force[p]
                                 : e.k * in[j].displacement[p] + e.c * in[j].velocity[p];
  }
  return r;
}

void Subsystem::apply_inputs(const CouplingData& in, const CouplingData* end, double t0) {
  drop_waveforms();
  check_inputs(in);
  if (end) check_inputs(*end);
  Loads start = loads_of(in);
  sys_.load = std::move(start.load);
  sys_.load_time = t0;
  sys_.load_rate.resize(0);
  std::optional<Loads> last;
  const double H = config_.macro_step;
  if (end) {
    last = loads_of(*end);
    sys_.load_rate = (last->load - sys_.load) / H;
  }
  for (std::size_t k = 0; k < sys_.contacts.size(); ++k) {
    ContactTerm& c = sys_.contacts[k];
    c.held_wheel = start.wheel[k];
    c.held_rail = start.rail[k];
    c.prescribed_force = start.force[k];
    c.held_wheel_rate = last ? (last->wheel[k] - start.wheel[k]) / H : 0.0;
    c.held_rail_rate = last ? (last->rail[k] - start.rail[k]) / H : 0.0;
    c.prescribed_force_rate = last ? (last->force[k] - start.force[k]) / H : 0.0;
    c.t0 = t0;
  }
  held_ = in;
  held_end_ = end ? *end : in;
  ramp_ = end != nullptr;
}

void Subsystem::accept_inputs(long n, const CouplingData& start, const CouplingData* end) {
  require(phase_ == Phase::kAwaitingInputs || phase_ == Phase::kInputsSet,
          "set_inputs(" + std::to_string(n) + ")",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  require(n == next_step_, "set_inputs(" + std::to_string(n) + ")",
          "the subsystem is at macro step " + std::to_string(next_step_));
  apply_inputs(start, end, time(n));
  // The held inputs changed the forces: restart from a consistent
  // acceleration, unless the run carries the integrator's across.
  if (!config_.carry_acceleration) newmark_->update_acceleration(time(n));
  phase_ = Phase::kInputsSet;
}

void Subsystem::set_inputs(long n, const CouplingData& inputs) {
  accept_inputs(n, inputs, nullptr);
}

void Subsystem::set_inputs(long n, const CouplingData& start, const CouplingData& end) {
  accept_inputs(n, start, &end);
}

CouplingData Subsystem::outputs() {
  require(phase_ == Phase::kAwaitingInputs || phase_ == Phase::kInputsSet, "outputs()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  // Inputs set for the coming step: those at its start; else those the last
  // step ended with.
  return compute_outputs(newmark_->state().u, newmark_->state().v, time(next_step_),
                         phase_ == Phase::kInputsSet ? held_ : held_end_);
}

CouplingData Subsystem::compute_outputs(const Vector& u, const Vector& v, double t,
                                        const CouplingData& held) const {
  const DofLayout& l = sys_.layout;
  const auto& ifs = config_.participant.interfaces;
  CouplingData out(ifs.size());
  for (std::size_t j = 0; j < ifs.size(); ++j) {
    const InterfaceSpec& i = ifs[j];
    InterfaceData& o = out[j];
    if (i.kind().moving) {
      for (std::size_t k = 0; k < sys_.contacts.size(); ++k) {
        if (i.side == CutSide::kLower) {
          const ContactPoint p = sys_.contacts[k].path.at(t);
          const auto e = static_cast<std::size_t>(p.element);
          o.displacement.push_back(p.shape[0] * u[l.rail_w[e]] + p.shape[1] * u[l.rail_theta[e]] +
                                   p.shape[2] * u[l.rail_w[e + 1]] +
                                   p.shape[3] * u[l.rail_theta[e + 1]]);
        } else if (i.sends_force()) {
          o.force.push_back(newmark_->contact_force(u, t, k));
        } else {
          o.displacement.push_back(u[l.wheels[k]]);
        }
      }
      continue;
    }
    const SpringDamper e = elements_[j];
    for (std::size_t p = 0; p < dofs_[j].size(); ++p) {
      const int dof = dofs_[j][p];
      if (i.sends_force()) {
        o.force.push_back(e.k * (u[dof] - held[j].displacement[p]) +
                          e.c * (v[dof] - held[j].velocity[p]));
      } else {
        o.displacement.push_back(u[dof]);
        o.velocity.push_back(v[dof]);
      }
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
  step_start_ = time(n);
  if (record_) {
    samples_.clear();
    take_sample(step_start_);
  }
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
  double soil = 0;
  for (int dof : l.soil) soil = std::max(soil, std::abs(s.u[dof]));
  r.max_abs_displacement = std::max(m, soil);
  const double t = time(next_step_);
  if (l.wheel >= 0) {
    r.history = {s.u[l.wheel], newmark_->contact_force(s.u, t)};
    if (sys_.contacts.size() > 1)
      for (std::size_t k = 0; k < sys_.contacts.size(); ++k)
        r.history.push_back(newmark_->contact_force(s.u, t, k));
  }
  if (!l.sleeper.empty() && scene_.ballast_forces) {
    // Below the sleepers: the soil held here, the ground, or the held
    // values of the ss interface this participant is the upper side of.
    const std::vector<double>*below_u = nullptr, *below_v = nullptr;
    const auto& ifs = config_.participant.interfaces;
    for (std::size_t j = 0; j < ifs.size(); ++j)
      if (ifs[j].kind().lower == Component::kSoil && ifs[j].side == CutSide::kUpper) {
        below_u = &held_end_[j].displacement;
        below_v = &held_end_[j].velocity;
      }
    for (double f : ballast_forces(scene_, l, s.u, s.v, below_u, below_v)) r.history.push_back(f);
  }
  if (!l.soil.empty()) r.history.push_back(soil);
  // After a step (or at the start): the inputs reached at its end.
  r.outputs = compute_outputs(s.u, s.v, t, held_end_);
  return r;
}

ParticipantResults Subsystem::results() {
  require(phase_ != Phase::kCreated && phase_ != Phase::kStepping, "results()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  ParticipantResults r;
  const Vector& u = newmark_->state().u;
  for (const auto* dofs : {&sys_.layout.rail_w, &sys_.layout.soil}) {
    if (dofs->empty()) continue;
    std::vector<double> f;
    for (int dof : *dofs) f.push_back(u[dof]);
    r.fields.push_back(std::move(f));
  }
  r.micro_steps = newmark_->state().micro_steps;
  return r;
}

}  // namespace railcosim
