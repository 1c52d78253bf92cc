// A co-simulation subsystem: the part of the wheel/track model on one side of
// a cut, integrated with its own adaptive micro steps between communication
// points.
//
//   split  side  holds                        receives (held over a macro step)
//   W/R    S1    wheel                        rail displacement under the wheel
//   W/R    S2    rail, pads, sleepers         X-X: wheel displacement; X-T: contact force
//   R/S    S1    wheel, contact, rail         sleeper displacements and velocities
//   R/S    S2    sleepers, ballast            X-X: rail displacements and velocities
//                                             at the pads; X-T: pad forces
//
// A side that receives a displacement computes the coupling force itself from
// its own state and the held value. Outputs are what the other side receives.
#pragma once

#include <memory>

#include "cosim_case.hpp"
#include "newmark.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "track_model.hpp"

namespace railcosim {

struct SubsystemConfig {
  Split split = Split::kWheelRail;
  Side side = Side::kS1;
  Coupling coupling = Coupling::kXX;
  double macro_step = 0;                                 // H, s
  double tolerance = 0;                                  // local error bound of the micro steps, m
  long max_micro_steps = Newmark::kMaxStepsPerInterval;  // per macro step, see Newmark
};

class Subsystem final : public Participant {
 public:
  Subsystem(const Scene& scene, const SubsystemConfig& config);
  Subsystem(const Subsystem&) = delete;
  Subsystem& operator=(const Subsystem&) = delete;

  std::string name() const override;
  StepResult initialize() override;
  void set_inputs(long n, const CouplingData& inputs) override;
  CouplingData outputs() override;
  void start_step(long n) override;
  StepResult finish_step() override;
  ParticipantResults results() override;
  ParticipantState save() override;
  void restore(const ParticipantState& state) override;

  // For tests: the integrator state.
  const NewmarkState& integrator_state() const { return newmark_->state(); }
  const Structure& structure() const { return sys_; }

 private:
  enum class Phase { kCreated, kAwaitingInputs, kInputsSet, kStepping };

  void require(bool ok, const std::string& call, const std::string& why) const;
  void apply_inputs(const CouplingData& in);
  void check_inputs(const CouplingData& in) const;
  double time(long n) const { return static_cast<double>(n) * config_.macro_step; }
  StepResult report() const;
  CouplingData compute_outputs() const;

  Scene scene_;
  SubsystemConfig config_;
  int points_ = 0;  // coupling points
  Structure sys_;
  Vector base_load_;
  std::unique_ptr<Newmark> newmark_;
  Phase phase_ = Phase::kCreated;
  long next_step_ = 0;  // the macro step the subsystem is at the start of
  CouplingData held_;
};

}  // namespace railcosim
