// The soils the master starts itself as participants of their own (Python
// programs on the participant SDK, in this source tree), by their [soil]
// model: one row each. The scene hands such a soil its whole [soil] table;
// the master starts `python3 -m MODULE` for the soil role (master/remote's
// NodePool) and gives it longer to start and to answer.
#pragma once

#include <string>

namespace railcosim {

struct OutsideSoil {
  const char* model;   // [soil] model
  const char* module;  // the Python module the master runs (python3 -m MODULE)
  const char* title;   // how messages name it
  bool mpi;            // it takes [soil] ranks (runs under mpirun when ranks > 1)
  bool force_only;     // it serves ss-xt only (takes the ballast force)
};

inline constexpr OutsideSoil kOutsideSoils[] = {
    {"fe", "fe_soil.participant", "the FE soil", true, true},
    {"green", "green_soil.participant", "the Green's-function soil", false, true},
};

// The row of a [soil] model the master starts itself; nullptr for any other.
inline const OutsideSoil* find_outside_soil(const std::string& model) {
  for (const OutsideSoil& s : kOutsideSoils)
    if (model == s.model) return &s;
  return nullptr;
}

}  // namespace railcosim
