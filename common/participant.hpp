// The interface between the master and one co-simulation subsystem.
//
// The master's schedules drive participants through this interface only: an
// in-process Subsystem and a proxy for a subsystem on a remote node are two
// implementations of it, so a schedule never knows where a subsystem lives.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "waveform.hpp"

namespace railcosim {

// The values of one interface at a communication point, one entry per
// coupling point (1 at the wheel/rail cut, one per sleeper at rs and ss), as
// packed arrays per quantity. A quantity the interface does not carry in
// that direction is left empty.
struct InterfaceData {
  std::vector<double> displacement;  // m, positive down
  std::vector<double> velocity;      // m/s
  std::vector<double> force;         // N, on the lower side of the cut, positive down

  bool operator==(const InterfaceData&) const = default;
};

// What a participant receives or sends: one entry per interface, in the
// order of its ParticipantSpec (the cut above it first).
using CouplingData = std::vector<InterfaceData>;

// A participant's outputs at one time inside a macro step: at its start and
// after each of its micro steps (substep samples).
struct OutputSample {
  double t = 0;
  CouplingData outputs;
};
using OutputSamples = std::vector<OutputSample>;

// Inputs over a macro step as waveforms, one per interface (in the order of
// CouplingData); each sample holds the interface's values packed by
// pack_values().
using InputWaveforms = std::vector<Waveform>;

// An interface's values as one array: displacements, velocities, forces.
inline std::vector<double> pack_values(const InterfaceData& d) {
  std::vector<double> v = d.displacement;
  v.insert(v.end(), d.velocity.begin(), d.velocity.end());
  v.insert(v.end(), d.force.begin(), d.force.end());
  return v;
}
// The inverse of pack_values() for values shaped like `shape` (only the
// sizes of its arrays count). `v` must have as many values as `shape`.
inline InterfaceData unpack_values(const std::vector<double>& v, const InterfaceData& shape) {
  InterfaceData d;
  auto at = v.begin();
  for (auto [out, n] :
       {std::pair{&d.displacement, shape.displacement.size()},
        std::pair{&d.velocity, shape.velocity.size()}, std::pair{&d.force, shape.force.size()}}) {
    out->assign(at, at + static_cast<std::ptrdiff_t>(n));
    at += static_cast<std::ptrdiff_t>(n);
  }
  return d;
}

// One row of a run's history: the wheel's channels, which every scene has,
// and the values of any further declared channels (RunRecord names them).
struct HistoryRow {
  double t = 0;
  double wheel = 0;          // q, m (down)
  double contact_force = 0;  // N
  std::vector<double> extra;
};

// What one macro step left behind (or, from initialize(), the state at t = 0).
struct StepResult {
  CouplingData outputs;             // at the end of the step, with the inputs held over it
  double max_abs_displacement = 0;  // over every DOF, for the divergence check
  bool finite = true;               // false if any state value is NaN or infinite
  std::vector<double> history;      // the values of the declared history channels
};

// The outputs a participant declares: history channels (one value per
// communication point) and end-of-run result fields (one vector each).
struct Channels {
  std::vector<std::string> history;  // e.g. "wheel_m", "contact_force_N", "soil_peak_m"
  std::vector<std::string> results;  // e.g. "rail_w_m", "soil_m"
};

// The final results a participant holds: one vector per declared field.
struct ParticipantResults {
  std::vector<std::vector<double>> fields;  // in the order of Channels::results
  long micro_steps = 0;
};

// An opaque snapshot of a participant (bitwise restorable).
struct ParticipantState {
  std::vector<double> values;
  // The snapshot stayed with the participant's node, which restores it on
  // request (a remote participant in lock step); `values` is then empty.
  bool kept = false;
  bool operator==(const ParticipantState&) const = default;
};

// A call out of order: a bug in the caller.
class CallOrderError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// A request the participant cannot serve: settings it cannot run (adaptive
// micro steps for a solver with fixed ones), its own configuration missing
// or invalid. A node answers BAD_REQUEST with the message, at Configure as
// at any other request.
class BadRequestError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// An interface the participant cannot honour (a cut it has no side of, a
// number of points or quantities it cannot serve): BAD_INTERFACE. (Any other
// std::invalid_argument thrown at Configure is answered so too.)
class BadInterfaceError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Inputs or a state that do not fit the participant (wrong count, a
// non-finite value, a snapshot of another subsystem): BAD_REQUEST.
class BadInputError : public BadRequestError {
 public:
  using BadRequestError::BadRequestError;
};

// Call order (enforced; a call out of order throws CallOrderError):
//   statics(inputs)                    any number of times first: the participant's own static
//                                      equilibrium for these held values; returns its outputs
//   initialize(inputs)                 once: start from the static state for these inputs;
//                                      returns the outputs at t = 0
//   then for each macro step n = 0, 1, 2, ... in turn:
//     set_inputs(n, data)              at least once: the inputs held over [nH, (n+1)H]
//                                      (or set_inputs(n, start, end): inputs that ramp;
//                                      or set_input_waveforms(n, waveforms))
//     outputs()                        any number of times: outputs now, with the held inputs
//     start_step(n), finish_step()     advance to (n+1)H; nothing else in between
//   results(), save(), restore()       any time after initialize() (not inside a step)
// start_step/finish_step are split so that a schedule can start several
// participants before waiting for any (Jacobi over the network).
class Participant {
 public:
  virtual ~Participant() = default;

  virtual std::string name() const = 0;
  virtual Channels channels() const = 0;
  virtual CouplingData statics(const CouplingData& inputs) = 0;
  virtual StepResult initialize(const CouplingData& inputs) = 0;
  virtual void set_inputs(long n, const CouplingData& inputs) = 0;
  // Interpolated inputs: they ramp linearly from `start` at nH to `end` at
  // (n+1)H instead of being held at one value (same call order).
  virtual void set_inputs(long n, const CouplingData& start, const CouplingData& end) {
    (void)start;
    (void)end;
    throw CallOrderError(name() + ": set_inputs(" + std::to_string(n) +
                         ") rejected: this participant takes held inputs only");
  }
  // Substep waveforms: each input evaluated over [nH, (n+1)H] from its
  // Waveform, at every micro step (same call order as set_inputs).
  virtual void set_input_waveforms(long n, const InputWaveforms& inputs) {
    (void)inputs;
    throw CallOrderError(name() + ": set_input_waveforms(" + std::to_string(n) +
                         ") rejected: this participant takes no substep waveforms");
  }
  // From now on, record the outputs at the start of every macro step and
  // after each of its micro steps (off by default).
  virtual void record_samples(bool on) {
    if (on)
      throw CallOrderError(name() +
                           ": record_samples() rejected: this participant records no samples");
  }
  // The samples of the last step taken while recording (times increasing,
  // from nH to (n+1)H); empty before one.
  virtual OutputSamples step_samples() const {
    throw CallOrderError(name() + ": step_samples() rejected: this participant records no samples");
  }
  virtual CouplingData outputs() = 0;
  virtual void start_step(long n) = 0;
  virtual StepResult finish_step() = 0;
  virtual ParticipantResults results() = 0;
  virtual ParticipantState save() = 0;
  virtual void restore(const ParticipantState& state) = 0;

  StepResult step(long n) {
    start_step(n);
    return finish_step();
  }
};

}  // namespace railcosim
