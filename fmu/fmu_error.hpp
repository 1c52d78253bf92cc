// The error every refusal of the FMU host throws: its message names the FMU
// file (or instance), what was refused and what to fix.
#pragma once

#include <stdexcept>

namespace railcosim::fmu {

class FmuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace railcosim::fmu
