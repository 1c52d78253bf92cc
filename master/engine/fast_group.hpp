// The faster group of a multirate step (rate_plan.hpp): the participants at
// the finest window H, stepped M times per slow window by an executor of
// their own (the inner level), as one participant of the outer level.
//
// The group's interfaces are its members' interfaces to the slow side. Its
// inputs over a slow window (held, ramped or substep waveforms: whatever the
// outer level gives) become the values its views replay at every fine
// window; its outputs are its members' at the slow window's end, and its
// substep samples their values at each fine window's end. save() keeps a
// checkpoint of every member and of the inner executor; restore() returns
// to it, so an implicit outer step re-runs the fine windows bit for bit.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/coupling_options.hpp"
#include "engine/rate_plan.hpp"
#include "engine/step_executor.hpp"

namespace railcosim::engine {

// A slow participant seen from inside the fast group: its values over its
// window, replayed at the fine windows. It takes no inputs (it ignores
// them) and leads every stage of the inner plan.
class SlowView final : public Participant {
 public:
  // `start`: the values it shows before the first window (its static
  // outputs); `fine_step`: h, the fine window; `intervals`: its samples
  // divide a fine window into this many equal parts (at least one).
  SlowView(std::string name, CouplingData start, double fine_step, int intervals);
  // Its values over the next slow window, one waveform per interface (of
  // pack_values() width).
  void set_window(std::vector<Waveform> values) { window_ = std::move(values); }

  std::string name() const override { return name_; }
  Channels channels() const override { return {}; }
  CouplingData statics(const CouplingData&) override;
  StepResult initialize(const CouplingData&) override;
  void set_inputs(long, const CouplingData&) override {}
  void set_inputs(long, const CouplingData&, const CouplingData&) override {}
  void set_input_waveforms(long, const InputWaveforms&) override {}
  void record_samples(bool on) override { record_ = on; }
  OutputSamples step_samples() const override { return samples_; }
  CouplingData outputs() override { return now_; }
  void start_step(long n) override;
  StepResult finish_step() override;
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {}; }
  void restore(const ParticipantState&) override {}

 private:
  CouplingData at(double t) const;

  std::string name_;
  CouplingData shape_, now_;
  double h_;
  int intervals_;
  std::vector<Waveform> window_;
  bool record_ = false;
  OutputSamples samples_;
  long n_ = -1;
};

class FastGroup final : public Participant {
 public:
  // `all`: every participant of the case in load order; `static_inputs`:
  // their inputs in the coupled static state; `roles`: their names.
  FastGroup(const RatePlan& rates, const std::vector<Participant*>& all,
            const std::vector<CouplingData>& static_inputs, PlanOptions plan,
            CouplingOptions coupling, const std::vector<std::string>& roles, double fine_step);

  // The members' results at each fine window of the last slow window (by
  // member, in the order of RatePlan::fast), and at t = 0 after initialize().
  const std::vector<std::vector<StepResult>>& fine_results() const { return fine_; }
  const StepExecutor& inner() const { return *inner_; }
  // The state between slow windows, set from outside (the stability map):
  // the group's outputs and the inner level's memory.
  void set_outputs(CouplingData out) { last_ = std::move(out); }
  void set_inner_memory(StepExecutor::Memory m) { inner_->set_memory(std::move(m)); }

  std::string name() const override { return name_; }
  Channels channels() const override { return {}; }
  CouplingData statics(const CouplingData&) override;
  StepResult initialize(const CouplingData&) override;
  void set_inputs(long n, const CouplingData& inputs) override;
  void set_inputs(long n, const CouplingData& start, const CouplingData& end) override;
  void set_input_waveforms(long n, const InputWaveforms& inputs) override;
  void record_samples(bool on) override { record_ = on; }
  OutputSamples step_samples() const override { return samples_; }
  CouplingData outputs() override { return last_; }
  void start_step(long n) override { n_ = n; }
  StepResult finish_step() override;
  ParticipantResults results() override { return {}; }
  ParticipantState save() override;
  void restore(const ParticipantState& state) override;

 private:
  // The group's outputs and result from its members' results.
  StepResult group_result(const std::vector<StepResult>& members) const;
  // Hands each view its interfaces' waveforms (group input g is view
  // view_of_[g].first's interface view_of_[g].second).
  void to_views(const InputWaveforms& w);
  // Appends fine window n's samples of the group's outputs (`end`: at its end).
  void record_window(long n, const CouplingData& end);

  std::string name_;
  RatePlan rates_;
  std::vector<Participant*> members_;
  std::vector<std::unique_ptr<SlowView>> views_;
  std::vector<std::pair<std::size_t, std::size_t>> view_of_;
  std::size_t boundary_ = 0;  // see the constructor
  std::unique_ptr<StepExecutor> inner_;
  std::vector<CouplingData> inner_start_;  // the inner participants' static inputs
  double h_;
  bool record_ = false;
  OutputSamples samples_;
  CouplingData last_;
  std::vector<std::vector<StepResult>> fine_;
  long n_ = -1;
  // The checkpoint of save().
  std::vector<ParticipantState> kept_;
  StepExecutor::Checkpoint kept_inner_;
  CouplingData kept_last_;
};

}  // namespace railcosim::engine
