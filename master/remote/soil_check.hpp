// `master run --check` for a soil the master starts itself (an outside soil
// of its own, common/outside_soil.hpp): the soil's program is asked whether
// it would accept the Configure the run would send it (its --check-configure
// mode: the keys, the interface and the sizes they imply, nothing built),
// so that --check refuses what the run would refuse, naming the scene file
// and the key. No node is started and no port opened.
#pragma once

#include <chrono>
#include <string>

#include "cosim_case.hpp"
#include "scene.hpp"

namespace railcosim::remote {

// How long the soil's check may take (Python and its imports start).
inline constexpr std::chrono::seconds kSoilCheckTimeout{60};

// Throws std::invalid_argument with the soil's reason if it would refuse
// its configuration, std::runtime_error if it cannot be asked (not started,
// no answer within `timeout`). Nothing to do for a scene whose soil the
// master does not start, or a case without the soil participant.
void check_started_soil(const Scene& scene, const CaseSpec& spec, double macro_step,
                        std::chrono::milliseconds timeout = kSoilCheckTimeout);

}  // namespace railcosim::remote
