// The error every refusal of the FMU host throws: its message names the FMU
// file (or instance), what was refused and what to fix.
#pragma once

#include <stdexcept>
#include <string>

namespace railcosim::fmu {

class FmuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A step in which the FMU ended the simulation (FMI 2 fmi2Discard with
// fmi2Terminated, FMI 3 terminateSimulation): its values stand at `time`,
// the last time it reached, and it takes no further step.
class FmuTerminated : public FmuError {
 public:
  FmuTerminated(const std::string& what, double at) : FmuError(what), time(at) {}
  double time;
};

}  // namespace railcosim::fmu
