// A co-simulation subsystem: the components of the model one participant
// holds (see model.hpp), integrated with its own adaptive micro steps between
// communication points.
//
// Per interface (one side of a cut), following the model's rules (docs/model.md):
//   upper side   receives the lower side's displacements (and velocities
//                through a damped layer) and computes the layer's force;
//                sends its own displacements (X-X) or that force (X-T)
//   lower side   receives displacements (X-X) or the force (X-T); sends its
//                own displacements (and velocities through a damped layer)
// A received value is held constant over the macro step, ramps linearly over
// it, or follows a Waveform of the sender's substep samples (evaluated at
// every micro step, subsystem_waveform.cpp).
#pragma once

#include <memory>

#include "model.hpp"
#include "newmark.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "track_model.hpp"

namespace railcosim {

struct SubsystemConfig {
  ParticipantSpec participant;
  double macro_step = 0;  // H, s
  double tolerance = 0;   // local error bound of the micro steps, m
  int micro_steps = 0;    // > 0: fixed micro steps per macro step
  // At a communication point: false (consistent) restarts from the
  // acceleration the new inputs imply; true (carry) keeps the integrator's.
  bool carry_acceleration = false;
  long max_micro_steps = Newmark::kMaxStepsPerInterval;  // per macro step, see Newmark
};

// A participant's configuration for a run of `scene` at macro step H with
// micro-step tolerance `tolerance`: the scene's micro steps and restart
// convention.
SubsystemConfig subsystem_config(const Scene& scene, const ParticipantSpec& p, double macro_step,
                                 double tolerance);

// The number of coupling points of an interface (one per wheel at the
// contact, one per sleeper otherwise).
int interface_points(const Scene& scene, const InterfaceSpec& i);

// The history channels and result fields a participant holding these parts
// declares: with the vehicle, wheel_m (the leading wheel) and
// contact_force_N (the sum over the wheels), and with several wheels
// force_w1_N, force_w2_N, ...; with the sleepers and [output] ballast_forces,
// ballast_force_1_N, ... (into the ballast under each sleeper, positive
// down); with a soil, soil_peak_m.
Channels channels_of(const Scene& scene, const Parts& parts);

class Subsystem final : public Participant {
 public:
  Subsystem(const Scene& scene, const SubsystemConfig& config);
  Subsystem(const Subsystem&) = delete;
  Subsystem& operator=(const Subsystem&) = delete;

  std::string name() const override;
  Channels channels() const override { return channels_of(scene_, config_.participant.parts); }
  CouplingData statics(const CouplingData& inputs) override;
  StepResult initialize(const CouplingData& inputs) override;
  void set_inputs(long n, const CouplingData& inputs) override;
  void set_inputs(long n, const CouplingData& start, const CouplingData& end) override;
  void set_input_waveforms(long n, const InputWaveforms& inputs) override;
  void record_samples(bool on) override;
  OutputSamples step_samples() const override { return samples_; }
  CouplingData outputs() override;
  void start_step(long n) override;
  StepResult finish_step() override;
  ParticipantResults results() override;
  ParticipantState save() override;
  void restore(const ParticipantState& state) override;

  // Why `data` cannot be this participant's inputs at interface `j` (a
  // wrong number of values of a quantity, a non-finite value unless
  // `any_value`), or "" if it can.
  std::string input_fault(std::size_t j, const InterfaceData& data, bool any_value = false) const;

  // For tests: the integrator state.
  const NewmarkState& integrator_state() const { return newmark_->state(); }
  const Structure& structure() const { return sys_; }

 private:
  enum class Phase { kCreated, kAwaitingInputs, kInputsSet, kStepping };

  void require(bool ok, const std::string& call, const std::string& why) const;
  // Holds `in` from t0 on, ramping to `end` at t0 + H when given.
  void apply_inputs(const CouplingData& in, const CouplingData* end, double t0);
  struct Loads {
    Vector load;
    std::vector<double> wheel, rail, force;  // the contacts' held values, per wheel
  };
  Loads loads_of(const CouplingData& in) const;
  void accept_inputs(long n, const CouplingData& start, const CouplingData* end);
  void check_inputs(const CouplingData& in) const;
  double time(long n) const { return static_cast<double>(n) * config_.macro_step; }
  StepResult report() const;
  // Substep waveforms (subsystem_waveform.cpp): the shape of interface j's
  // inputs (zeros, sized as it receives), the inputs at time t of the step
  // started at t0, the load and contact values they make at t, and the
  // sample taken at t.
  InterfaceData input_shape(std::size_t j) const;
  CouplingData inputs_at(double t, double t0) const;
  void hold_loads(const CouplingData& in, double t);
  void take_sample(double t);
  void drop_waveforms();
  CouplingData compute_outputs(const Vector& u, const Vector& v, double t,
                               const CouplingData& held) const;

  Scene scene_;
  SubsystemConfig config_;
  std::vector<int> points_;             // per interface
  std::vector<std::vector<int>> dofs_;  // per interface: own DOFs of a linear layer
  std::vector<SpringDamper> elements_;  // per interface: the layer's element
  Structure sys_;
  Vector base_load_;
  Vector static_u_;  // the last static solution, the next one's starting guess
  std::unique_ptr<Newmark> newmark_;
  Phase phase_ = Phase::kCreated;
  long next_step_ = 0;     // the macro step the subsystem is at the start of
  CouplingData held_;      // the inputs at the start of the macro step
  CouplingData held_end_;  // and at its end (the same for a zero-order hold)
  bool ramp_ = false;
  InputWaveforms waves_;   // substep waveforms over the step, or empty
  bool record_ = false;    // record the outputs at every micro step
  double step_start_ = 0;  // the time the step being taken started
  OutputSamples samples_;  // those of the last step
};

}  // namespace railcosim
