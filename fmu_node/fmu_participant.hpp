// An FMU (FMI 2.0 or 3.0 co-simulation) as a participant: the FMU's
// variables mapped to the interfaces the master describes, its parameters
// set from its configuration, one FMU communication step per macro step
// with the inputs held over it, or ramped where the FMU follows input
// derivatives (FMI 2 canInterpolateInputs). Its configuration (the table of --config,
// docs/fmu.md):
//   file = "vehicle.fmu"                 the FMU, relative to the config file
//   CUT_in_QUANTITY = "name_{i}"         the FMU input of each quantity an
//   CUT_out_QUANTITY = "name_{i}"        interface receives / output of each it
//                                        sends; {i} is the coupling point, 0, 1, ...
//   set_NAME = 2.5                       a parameter's start value
//   peak_history = "soil_peak_m"         optional: a history channel of that name,
//                                        the largest |displacement| it sends
//   history_NAME = "name"                optional: a history channel NAME, that
//                                        variable at each communication point
//   result_NAME = "name_{i}"             optional: a result field NAME, those
//                                        variables at the end (i = 0, 1, ... while
//                                        the FMU has them)
// (CUT: wr, rs, ss; QUANTITY: displacement, velocity, force). Refused with
// a BadRequestError naming the key: a missing or unknown key, a variable
// the FMU lacks, of another causality or type, or whose declared unit is
// not the interface's (m, m/s, N).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fmu.hpp"
#include "participant.hpp"
#include "participant_setup.hpp"

namespace railcosim {

class FmuParticipant final : public Participant {
 public:
  explicit FmuParticipant(const ParticipantSetup& setup);
  ~FmuParticipant() override;

  std::string name() const override;
  Channels channels() const override { return channels_; }
  // Before initialize(): the FMU in its initialization mode, these inputs
  // set, its outputs read (an FMU has no statics of its own to solve).
  CouplingData statics(const CouplingData& inputs) override;
  StepResult initialize(const CouplingData& inputs) override;
  void set_inputs(long n, const CouplingData& inputs) override;
  // Inputs that ramp over the step: the values at its start and their slope
  // (end - start) / H as first derivatives (FMI 2 input derivatives), for an
  // FMU that interpolates its inputs; refused, saying so, by one that does
  // not (it takes held inputs only).
  void set_inputs(long n, const CouplingData& start, const CouplingData& end) override;
  CouplingData outputs() override;
  void start_step(long n) override;
  StepResult finish_step() override;
  ParticipantResults results() override;
  // The FMU's state, kept here (at most kKeptStates, the oldest dropped);
  // the snapshot names it. Refused for an FMU that cannot save its state.
  ParticipantState save() override;
  void restore(const ParticipantState& state) override;

  static constexpr std::size_t kKeptStates = 256;

  // What its FMU says it can do: follow input derivatives (ramped inputs),
  // save and restore its state (implicit coupling, a judgement).
  bool interpolates_inputs() const { return fmu_->interpolates_inputs(); }
  bool saves_state() const { return fmu_->description().capabilities.can_get_and_set_state; }
  // The default experiment's step where the FMU cannot vary its
  // communication step; nullopt where it can or gives none.
  std::optional<double> only_step() const {
    const fmu::ModelDescription& d = fmu_->description();
    if (d.capabilities.can_handle_variable_step) return std::nullopt;
    return d.default_experiment.step_size;
  }

 private:
  // One quantity of one interface: its value references, point by point.
  struct Port {
    std::size_t interface = 0;
    Quantity quantity = Quantity::kDisplacement;
    std::vector<std::uint32_t> refs;
  };
  void map_ports(const ParticipantSetup& setup);
  void check_inputs(long n, const CouplingData& inputs) const;
  void set_parameters(const OwnConfig& config);
  void declare_channels(const OwnConfig& config);
  void enter_initialization();
  StepResult report();

  std::unique_ptr<fmu::Fmu> fmu_;
  std::vector<Port> inputs_, outputs_;
  std::size_t interfaces_ = 0;
  std::vector<std::pair<std::uint32_t, double>> parameters_;
  Channels channels_;
  bool peak_history_ = false;
  std::vector<std::uint32_t> history_refs_;  // after the peak, in channels_.history's order
  std::vector<std::vector<std::uint32_t>> result_refs_;  // in the order of channels_.results
  double macro_step_ = 0;
  bool in_initialization_ = false;
  long next_ = -1;  // the next macro step (-1 before initialize)
  long steps_ = 0;
  std::map<long, fmu::FmuState> states_;
  long next_state_ = 0;
};

}  // namespace railcosim
