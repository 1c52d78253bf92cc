// How the master couples the participants over a macro step beyond the
// scheme (Jacobi or Gauss–Seidel): what the inputs do over the step, and
// whether the step is iterated to convergence.
#pragma once

#include <string>

#include "engine/accelerator.hpp"

namespace railcosim::engine {

// Inputs over [t_n, t_n + H]:
//   hold          the latest known value, held (the paper's zero-order hold);
//   linear        a ramp from the value at t_n to the value at t_n + H where
//                 that is known (Gauss–Seidel's later participants; every
//                 implicit iteration), held otherwise;
//   extrapolate1  a ramp to the value at t_n + H extrapolated from the last
//   extrapolate2  two (three) communication points where it is not known;
//                 explicit coupling only; fewer past points: a lower order;
//   waveform0..3  the sender's outputs at each of its micro steps of this
//                 step (common/waveform.hpp), interpolated with degree 0 to 3,
//                 where they are known (Gauss–Seidel's later participants;
//                 every implicit iteration after the first), held otherwise;
//                 in process only (--transport inproc).
enum class InputMode {
  kHold,
  kLinear,
  kExtrapolate1,
  kExtrapolate2,
  kWaveform0,
  kWaveform1,
  kWaveform2,
  kWaveform3
};
// explicit: one pass per macro step (the paper); implicit: each macro step is
// repeated from a checkpoint until the exchanged values converge.
enum class CouplingMethod { kExplicit, kImplicit };

std::string to_string(InputMode m);
// The interpolation degree of a waveform mode, or -1 for the others.
int waveform_degree(InputMode m);
std::string to_string(CouplingMethod m);
// Throw std::invalid_argument naming `what` (an option or a key) and the valid values.
InputMode parse_input_mode(const std::string& s, const std::string& what);
CouplingMethod parse_coupling_method(const std::string& s, const std::string& what);

// The default iteration budget of an implicit run, per macro step of it.
inline constexpr long kIterationsPerStep = 50;  // = the default max_iterations

struct CouplingOptions {
  CouplingMethod method = CouplingMethod::kExplicit;
  InputMode inputs = InputMode::kHold;
  AcceleratorOptions accelerator;  // implicit only
  int max_iterations = 50;         // implicit: per macro step
  // implicit: iterations over the whole run; 0: none (the run's own default,
  // kIterationsPerStep per macro step of the run, is set by the runner).
  long iteration_budget = 0;
  // implicit: converged when, for every exchanged quantity (one cut, one
  // direction, one of displacement/velocity/force), ||G(x) - x|| <=
  // convergence * the largest norm that quantity has had in the run so far
  // (for a velocity: or its displacement's largest norm / H, whichever is
  // larger, since a velocity error dv moves the displacement by dv H).
  // (The coupling libraries' plain relative measure, against ||G(x)||, never
  // converges on a quantity that starts at zero, such as the velocities at a
  // static start, whose first values are round-off.)
  double convergence = 1e-8;

  bool is_plain() const {
    return method == CouplingMethod::kExplicit && inputs == InputMode::kHold;
  }
  // "implicit-linear-iqn-ils", "explicit-extrapolate2", "explicit-hold", ...
  std::string label() const;
};

// Throws std::invalid_argument for values out of range, naming the option.
void check(const CouplingOptions& o);

}  // namespace railcosim::engine
