#include "engine/coupling_options.hpp"

#include <stdexcept>

namespace railcosim::engine {

std::string to_string(InputMode m) {
  switch (m) {
    case InputMode::kHold:
      return "hold";
    case InputMode::kLinear:
      return "linear";
    case InputMode::kExtrapolate1:
      return "extrapolate1";
    case InputMode::kExtrapolate2:
      return "extrapolate2";
    case InputMode::kWaveform0:
    case InputMode::kWaveform1:
    case InputMode::kWaveform2:
    case InputMode::kWaveform3:
      return "waveform" + std::to_string(waveform_degree(m));
  }
  return "?";
}

int waveform_degree(InputMode m) {
  switch (m) {
    case InputMode::kWaveform0:
      return 0;
    case InputMode::kWaveform1:
      return 1;
    case InputMode::kWaveform2:
      return 2;
    case InputMode::kWaveform3:
      return 3;
    default:
      return -1;
  }
}

std::string to_string(CouplingMethod m) {
  return m == CouplingMethod::kImplicit ? "implicit" : "explicit";
}

namespace {

[[noreturn]] void unknown(const std::string& what, const std::string& s, const char* valid) {
  std::string msg = what;
  msg += ": unknown value '";
  msg += s;
  msg += "' (";
  msg += valid;
  msg += ")";
  throw std::invalid_argument(msg);
}

}  // namespace

InputMode parse_input_mode(const std::string& s, const std::string& what) {
  for (InputMode m :
       {InputMode::kHold, InputMode::kLinear, InputMode::kExtrapolate1, InputMode::kExtrapolate2,
        InputMode::kWaveform0, InputMode::kWaveform1, InputMode::kWaveform2, InputMode::kWaveform3})
    if (to_string(m) == s) return m;
  unknown(what, s,
          "hold, linear, extrapolate1, extrapolate2, waveform0, waveform1, waveform2 or "
          "waveform3");
}

CouplingMethod parse_coupling_method(const std::string& s, const std::string& what) {
  for (CouplingMethod m : {CouplingMethod::kExplicit, CouplingMethod::kImplicit})
    if (to_string(m) == s) return m;
  unknown(what, s, "explicit or implicit");
}

std::string CouplingOptions::label() const {
  std::string s = to_string(method);
  s += '-';
  s += to_string(inputs);
  if (method == CouplingMethod::kImplicit) {
    s += '-';
    s += to_string(accelerator.kind);
  }
  return s;
}

void check(const CouplingOptions& o) {
  if (o.method == CouplingMethod::kImplicit &&
      (o.inputs == InputMode::kExtrapolate1 || o.inputs == InputMode::kExtrapolate2))
    throw std::invalid_argument(
        "--inputs " + to_string(o.inputs) +
        " applies to explicit coupling; implicit coupling knows the values at the end of the "
        "step from its iterations (use --inputs hold, linear or waveform0 to waveform3)");
  if (!(o.convergence > 0 && o.convergence < 1))
    throw std::invalid_argument("--convergence must be in (0, 1)");
  if (o.max_iterations < 1 || o.max_iterations > 10000)
    throw std::invalid_argument("--max-iterations must be in [1, 10000]");
  if (o.iteration_budget < 0 || o.iteration_budget > 10'000'000'000L)
    throw std::invalid_argument("--iteration-budget must be in [0, 10000000000]");
  if (!(o.accelerator.relaxation > 0 && o.accelerator.relaxation <= 1))
    throw std::invalid_argument("--relaxation must be in (0, 1]");
  if (o.accelerator.windows_reused < 0 || o.accelerator.windows_reused > 100)
    throw std::invalid_argument("--reused-windows must be in [0, 100]");
}

}  // namespace railcosim::engine
