// The one executor of a step plan (step_plan.hpp) on the master: it runs
// the participants over each macro step, stage after stage, whether they
// live in the master's process or are RemoteParticipant proxies of nodes
// over the relayed data plane.
//
// A macro step is a fixed-point iteration x = G(x) over the values at
// t_n + H of the plan's iterated links; explicit coupling is the case with
// one iteration and no unknowns:
//   - explicit: one pass; a link whose value at t_n + H is not stepped
//     before its receiver holds its value at t_n (`hold`, the paper's
//     schedules), or ramps to the value extrapolated from the last points
//     (`extrapolate1|2`);
//   - implicit: the participants are saved before the step and restored
//     before every further pass; the accelerator proposes the next x from x
//     and G(x) until every exchanged quantity has converged.
// Inputs ramp (`linear`) from the value at t_n to the one at t_n + H where
// that is known; otherwise they are held at the last known value.
// Substep waveforms (`waveform0..3`): every participant records its outputs
// at its micro steps, and a receiver takes each input as a Waveform of the
// sender's samples where they are known: those of this pass for a sender of
// an earlier stage; for an iterated link, those of the last iteration plus a
// correction that makes them pass through the accelerator's values at
// kWaveNodes times of the window (the accelerator works on those values: an
// adaptive sender's samples vary in number from one iteration to the next;
// at convergence the correction vanishes); in an implicit step's first
// iteration, the waveform through those values. Elsewhere the input is held.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/accelerator.hpp"
#include "engine/convergence.hpp"
#include "engine/coupling_options.hpp"
#include "engine/step_plan.hpp"

namespace railcosim::engine {

// The macro steps of a run, whichever plane carries them.
class MacroSteps {
 public:
  virtual ~MacroSteps() = default;
  // The results of macro step n, from nH to (n+1)H.
  virtual std::vector<StepResult> advance(long n) = 0;
};

// What a run and the stability measures step on the master: the executor
// of a plan at one rate (StepExecutor) or at two (MultirateExecutor).
class CoupledSteps : public MacroSteps {
 public:
  // The master's part of the coupled state between macro steps: every
  // participant's outputs at t_n and, for extrapolated inputs, at the points
  // before. With the participants' states it is the state an explicit
  // coupling's macro step maps (run/spectral.hpp reads and sets it).
  struct Memory {
    std::vector<CouplingData> out;
    std::vector<std::vector<CouplingData>> past;
  };
  virtual Memory memory() const = 0;
  virtual void set_memory(Memory m) = 0;
  // Initialises every participant with its inputs at t = 0 (the coupled
  // static state); returns their results.
  virtual std::vector<StepResult> initialize(const std::vector<CouplingData>& inputs) = 0;
  // The iterations of an implicit coupling (of the slowest level).
  virtual const ConvergenceLog& log() const = 0;
  // The finest windows one step of the coupled map spans (a multirate
  // plan's slow window; else 1).
  virtual long map_windows() const { return 1; }
  // The next implicit step takes its first pass only, its iterate the
  // memory's values at t_n: the matrix-free measure (run/matrix_free.hpp)
  // moves the participants' inner states this way, which a converged step
  // would not let the memory reach. An explicit coupling ignores it.
  virtual void single_pass_next() = 0;
  // Step N of the coupled map: finest windows N * map_windows() onwards;
  // returns the results of the last.
  std::vector<StepResult> advance_map(long N) {
    std::vector<StepResult> r;
    for (long k = 0; k < map_windows(); ++k) r = advance(N * map_windows() + k);
    return r;
  }
};

class StepExecutor : public CoupledSteps {
 public:
  // The participants in load order (they must outlive the executor); `roles`
  // name them in the convergence log (implicit coupling only: may be empty
  // otherwise). Throws std::invalid_argument for options that do not exist.
  StepExecutor(std::vector<Participant*> participants, Routing routing, PlanOptions plan,
               CouplingOptions coupling = {}, std::vector<std::string> roles = {},
               double macro_step = 0);

  // Initialises every participant with its inputs at t = 0 (the coupled
  // static state), keeps their outputs and compiles the plan (which
  // participants send forces is read from these outputs).
  std::vector<StepResult> initialize(const std::vector<CouplingData>& inputs) override;
  // Exchanges and steps from nH to (n+1)H as the plan says.
  std::vector<StepResult> advance(long n) override;

  Memory memory() const override { return {out_, past_}; }
  // Sets the state between macro steps; no pass of the next step has run.
  void single_pass_next() override { single_pass_ = true; }
  void set_memory(Memory m) override {
    out_ = std::move(m.out);
    past_ = std::move(m.past);
    last_step_ = -1;
  }

  // A checkpoint of the executor's own state between macro steps: its
  // memory and what its accelerator has learnt (the participants' states are
  // their own). The faster group of a multirate step re-runs its windows
  // from one, so that a pass repeats bit for bit.
  struct Checkpoint {
    Memory memory;
    std::shared_ptr<const Accelerator> accel;  // null before the first implicit step
    std::vector<double> largest;
  };
  Checkpoint checkpoint() const;
  void restore(const Checkpoint& c);

  // Before initialize(): participants whose values over a step are known
  // before it (plan_steps()' `leads`; one flag per participant).
  void set_leading(std::vector<bool> leads) { leads_ = std::move(leads); }

  // The plan, once initialize() has compiled it.
  const StepPlan& plan() const { return plan_; }
  // The iterations of an implicit coupling (empty for an explicit one).
  const ConvergenceLog& log() const override { return log_; }

 private:
  // Runs every participant over step n once, stage after stage; `x` gives
  // the values at t_n + H of the iterated links (implicit), or is null.
  std::vector<StepResult> pass(long n, const std::vector<InterfaceData>* x);
  // Sets participant p's inputs of step n: each link's value at t_n (the
  // refreshed one where `refreshed` holds it), ending at `end` where given.
  void set_inputs(std::size_t p, long n, const std::vector<CouplingData>* refreshed,
                  const std::vector<const InterfaceData*>& end);
  // The value at t_n + H of link k where the plan does not step its sender
  // first: x's (implicit) or an extrapolation (explicit), else null.
  const InterfaceData* end_value(std::size_t k, const std::vector<InterfaceData>* x,
                                 std::vector<InterfaceData>& extrapolated) const;
  // Substep waveforms: participant p's inputs of step n as waveforms.
  void set_waveforms(std::size_t p, long n, const std::vector<CouplingData>* refreshed,
                     const std::vector<const InterfaceData*>& end);
  // The waveform of link k for step n (see set_waveforms), `start` its value
  // at t_n and `end` its value at t_n + H where known.
  Waveform link_waveform(std::size_t k, long n, const InterfaceData& start,
                         const InterfaceData* end) const;
  // The k-th of the nodes_ times of step n's window (the last: t_n + H).
  double node_time(long n, std::size_t k) const;
  // Interface i of a sender's samples at the nodes, stacked (one node: the
  // last sample).
  InterfaceData at_nodes(const OutputSamples& samples, std::size_t i, long n) const;
  std::vector<StepResult> implicit_step(long n);
  // Implicit coupling: the blocks of x (one per iterated link and quantity
  // it carries), their names and the accelerator, from the first step.
  void make_blocks();
  // Logs iteration k's residual per block; true when every one converged.
  // `scale`: the accelerator's weight per block.
  bool measure(long n, int k, const Eigen::VectorXd& x, const Eigen::VectorXd& gx,
               std::vector<double>& scale);

  std::vector<Participant*> ps_;
  std::vector<bool> leads_;
  Routing routing_;
  PlanOptions plan_options_;
  CouplingOptions o_;
  std::vector<std::string> roles_;
  double macro_step_;
  StepPlan plan_;
  std::vector<CouplingData> out_;                // every participant's outputs at t_n
  std::vector<std::vector<CouplingData>> past_;  // outputs at t_{n-1}, t_{n-2} (extrapolation)
  std::vector<std::size_t> iterated_;            // implicit: the links of x, in order
  std::vector<int> position_;                    // per link: its index in x, or -1
  std::vector<int> blocks_;                      // implicit: the length of each block of x
  std::vector<int> displacement_of_;  // per velocity block: its displacement's block, or -1
  std::unique_ptr<Accelerator> accel_;
  std::vector<double> largest_;  // per quantity: the largest norm it has had in the run
  ConvergenceLog log_;
  int degree_ = -1;        // substep waveforms: their degree, else -1
  std::size_t nodes_ = 1;  // values per iterated link in x (waveforms, implicit: kWaveNodes)
  std::vector<OutputSamples> fresh_;  // per participant: the samples of this pass
  std::vector<OutputSamples> last_;   // and of the last pass
  long last_step_ = -1;               // the macro step of last_
  bool single_pass_ = false;          // the next implicit step: its first pass only
};

}  // namespace railcosim::engine
