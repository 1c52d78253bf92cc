// An FMU in the master's own process under --transport inproc: a
// participant the scene maps to an FMU (Scene::fmu_mapping: the vehicle's
// [vehicle.fmu]; a soil whose [soil] table says model = "external" and
// names an FMU, file = "soil.fmu", with the FMU participant's keys,
// docs/fmu.md). The
// participant is the one fmu_node serves (fmu_node/fmu_participant.hpp),
// given the setup a node would be given (the Configure the master would
// send it, read as a node reads it), so that the run is the same run bit
// for bit, without a socket. The FMU's binary runs in the master's process
// with the user's rights; a relative `file` is the scene file's neighbour.
#pragma once

#include <memory>
#include <optional>

#include "cosim_case.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim::remote {

// The participant for `config` when the scene maps its role to an FMU;
// nullptr otherwise.
// Throws std::invalid_argument naming the scene's key for a mapping the FMU
// participant refuses.
std::unique_ptr<Participant> inproc_fmu(const Scene& scene, const SubsystemConfig& config);

// What the FMU the scene maps to `config`'s role can take part in, read
// from its description once its participant is made for that case (so a
// mapping that does not fit the case's interfaces throws, as a run would).
struct FmuAbilities {
  bool ramps = false;  // ramped and extrapolated inputs: it follows input derivatives
  bool state = false;  // implicit coupling and a judgement: it saves its state
  // Where it cannot vary its communication step (canHandleVariableCommunicationStepSize
  // not true) and its default experiment gives one: that step, the only macro
  // step a study can be sure it takes.
  std::optional<double> only_step;
};
// nullopt when the scene maps that role to no FMU.
std::optional<FmuAbilities> fmu_abilities(const Scene& scene, const SubsystemConfig& config);

}  // namespace railcosim::remote
