// Substep waveforms in a subsystem: inputs that follow a Waveform of their
// sender's samples over the macro step, and the samples this subsystem
// records of its own outputs at every micro step.
#include <cmath>

#include "subsystem.hpp"

namespace railcosim {

InterfaceData Subsystem::input_shape(std::size_t j) const {
  InterfaceData d;
  const std::vector<double> zeros(static_cast<std::size_t>(points_[j]), 0.0);
  for (Quantity q : config_.participant.interfaces[j].receives()) {
    if (q == Quantity::kDisplacement) d.displacement = zeros;
    if (q == Quantity::kVelocity) d.velocity = zeros;
    if (q == Quantity::kForce) d.force = zeros;
  }
  return d;
}

CouplingData Subsystem::inputs_at(double t, double t0) const {
  if (!waves_.empty()) {
    CouplingData in;
    for (std::size_t j = 0; j < waves_.size(); ++j)
      in.push_back(unpack_values(waves_[j].at(t), input_shape(j)));
    return in;
  }
  if (!ramp_) return held_;
  // A ramp from held_ at t0 to held_end_ at t0 + H.
  const double s = (t - t0) / config_.macro_step;
  CouplingData in = held_;
  for (std::size_t j = 0; j < in.size(); ++j) {
    const std::vector<double> a = pack_values(held_[j]), b = pack_values(held_end_[j]);
    std::vector<double> v(a.size());
    for (std::size_t k = 0; k < a.size(); ++k) v[k] = a[k] + s * (b[k] - a[k]);
    in[j] = unpack_values(v, held_[j]);
  }
  return in;
}

void Subsystem::hold_loads(const CouplingData& in, double t) {
  Loads l = loads_of(in);
  sys_.load = std::move(l.load);
  sys_.load_time = t;
  sys_.load_rate.resize(0);
  for (std::size_t k = 0; k < sys_.contacts.size(); ++k) {
    ContactTerm& c = sys_.contacts[k];
    c.held_wheel = l.wheel[k];
    c.held_rail = l.rail[k];
    c.prescribed_force = l.force[k];
    c.held_wheel_rate = c.held_rail_rate = c.prescribed_force_rate = 0.0;
    c.t0 = t;
  }
}

void Subsystem::drop_waveforms() {
  if (waves_.empty()) return;
  waves_.clear();
  newmark_->set_input_hook({});
}

void Subsystem::set_input_waveforms(long n, const InputWaveforms& inputs) {
  const auto& ifs = config_.participant.interfaces;
  if (inputs.size() != ifs.size())
    throw BadInputError(name() + ": input waveforms rejected: expected " +
                        std::to_string(ifs.size()) + " interface(s), got " +
                        std::to_string(inputs.size()));
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    const std::size_t width = pack_values(input_shape(j)).size();
    if (inputs[j].width() != width || inputs[j].samples() == 0)
      throw BadInputError(name() + ": input waveforms rejected: interface " + std::to_string(j) +
                          " needs samples of " + std::to_string(width) + " values");
  }
  // The values at both ends set the step up as a ramp would (checked, kept
  // for save() and the outputs); inside it the waveforms take over.
  const double t0 = time(n), t1 = time(n + 1);
  CouplingData start, end;
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    start.push_back(unpack_values(inputs[j].at(t0), input_shape(j)));
    end.push_back(unpack_values(inputs[j].at(t1), input_shape(j)));
  }
  accept_inputs(n, start, &end);
  waves_ = inputs;
  newmark_->set_input_hook([this](double t) { hold_loads(inputs_at(t, t), t); });
}

void Subsystem::record_samples(bool on) {
  record_ = on;
  samples_.clear();
  if (on)
    newmark_->set_step_observer([this](double t, int) { take_sample(t); });
  else
    newmark_->set_step_observer({});
}

void Subsystem::take_sample(double t) {
  const NewmarkState& s = newmark_->state();
  samples_.push_back({t, compute_outputs(s.u, s.v, t, inputs_at(t, step_start_))});
}

}  // namespace railcosim
