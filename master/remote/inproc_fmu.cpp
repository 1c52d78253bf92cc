#include "remote/inproc_fmu.hpp"

#include <stdexcept>

#include "fmu_participant.hpp"
#include "newmark.hpp"
#include "setup_from_configure.hpp"
#include "wire.hpp"

namespace railcosim::remote {

std::unique_ptr<Participant> inproc_fmu(const Scene& scene, const SubsystemConfig& config) {
  const std::string& role = config.participant.role;
  const std::string mapping = scene.fmu_mapping(role);
  if (mapping.empty()) return nullptr;
  const std::string table = role == "vehicle" ? "vehicle.fmu" : role;
  const wire::Envelope e = configure_envelope(scene, config, false);
  try {
    ParticipantSetup setup =
        setup_from_configure(e.configure(), config.participant.role, Newmark::kMaxStepsPerInterval);
    // The scene file is the configuration's source: a relative `file` is
    // found beside it.
    setup.config = OwnConfig::parse(mapping, scene.source, table);
    return std::make_unique<FmuParticipant>(setup);
  } catch (const BadRequestError& b) {
    throw std::invalid_argument("the " + role + " FMU in process: " + b.what());
  } catch (const ProtocolError& p) {
    throw std::invalid_argument("the " + role + " FMU in process: " + p.what());
  }
}

std::optional<FmuAbilities> fmu_abilities(const Scene& scene, const SubsystemConfig& config) {
  const std::unique_ptr<Participant> p = inproc_fmu(scene, config);
  if (p == nullptr) return std::nullopt;
  const auto& fmu = static_cast<const FmuParticipant&>(*p);
  return FmuAbilities{fmu.interpolates_inputs(), fmu.saves_state(), fmu.only_step()};
}

}  // namespace railcosim::remote
