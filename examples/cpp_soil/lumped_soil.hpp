// The lumped soil of docs/model.md (`[soil] model = "lumped"`): a soil mass under
// each sleeper on a spring and damper to the ground, tied to its
// neighbours, loaded through the ballast from the sleepers above (the lower
// side of the ss cut). It knows the coupling from the interface the master
// describes (points, what it receives and sends, the ballast's stiffness
// and damping) and its own model from its own configuration (the [soil]
// table of --config: mass, stiffness, damping, coupling_stiffness,
// coupling_damping). Its own physics, written from the model alone:
// Newmark (beta = 1/4, gamma = 1/2) with a fixed number of equal micro steps
// per macro step, restarted at each communication point from the
// acceleration consistent with the new inputs.
#pragma once

#include <Eigen/Dense>
#include <string>

#include "participant.hpp"
#include "participant_setup.hpp"

class LumpedSoil final : public railcosim::Participant {
 public:
  // Throws railcosim::BadRequestError for a configuration or settings it
  // cannot serve, railcosim::BadInterfaceError for interfaces.
  explicit LumpedSoil(const railcosim::ParticipantSetup& setup);

  std::string name() const override { return "lumped soil (examples/cpp_soil)"; }
  railcosim::Channels channels() const override { return {{"soil_peak_m"}, {"soil_m"}}; }
  railcosim::CouplingData statics(const railcosim::CouplingData& inputs) override;
  railcosim::StepResult initialize(const railcosim::CouplingData& inputs) override;
  void set_inputs(long n, const railcosim::CouplingData& inputs) override;
  void set_inputs(long n, const railcosim::CouplingData& start,
                  const railcosim::CouplingData& end) override;
  // Substep waveforms (--inputs waveform0..3): the load at each micro
  // step's end from the waveforms, and the outputs recorded after each.
  void set_input_waveforms(long n, const railcosim::InputWaveforms& inputs) override;
  void record_samples(bool on) override { record_ = on; }
  railcosim::OutputSamples step_samples() const override { return samples_; }
  railcosim::CouplingData outputs() override;
  void start_step(long n) override;
  railcosim::StepResult finish_step() override;
  railcosim::ParticipantResults results() override;
  railcosim::ParticipantState save() override;
  void restore(const railcosim::ParticipantState& state) override;

 private:
  Eigen::VectorXd load_of(const railcosim::CouplingData& in) const;
  Eigen::VectorXd load_at(double t) const;  // from the waveforms
  void restart();
  railcosim::StepResult report() const;

  long n_ = 0;                   // soil masses (= sleepers)
  bool receives_force_ = false;  // X-T: the ballast force; X-X: sleeper displacement, velocity
  double kb_ = 0, cb_ = 0;       // the ballast, from the interface
  double H_ = 0, h_ = 0;         // macro and micro step
  int m_ = 0;                    // micro steps per macro step
  Eigen::MatrixXd M_, C_, K_;
  Eigen::LDLT<Eigen::MatrixXd> Keff_, Kstat_;
  Eigen::VectorXd u_, v_, a_, load_, rate_;
  bool carry_ = false;  // keep the integrator's acceleration at communication points
  long next_ = -1;      // the next macro step (-1 before initialize)
  long micro_steps_ = 0;
  railcosim::InputWaveforms waves_;  // this step's, when it has them
  bool record_ = false;
  railcosim::OutputSamples samples_;  // of the last step, while recording
};
