#include "remote/inproc_fmu.hpp"

#include <stdexcept>

#include "fmu_participant.hpp"
#include "newmark.hpp"
#include "setup_from_configure.hpp"
#include "wire.hpp"

namespace railcosim::remote {
namespace {

bool is_soil(const SubsystemConfig& c) {
  return c.participant.role == "soil" && c.participant.parts.has(Component::kSoil);
}

}  // namespace

bool soil_fmu_in_process(const Scene& scene) {
  if (scene.soil_model != "external" || scene.soil_config.empty()) return false;
  const OwnConfig config = OwnConfig::parse(scene.soil_config, scene.source, "soil");
  return config.has("file");
}

std::unique_ptr<Participant> inproc_fmu(const Scene& scene, const SubsystemConfig& config) {
  if (!is_soil(config) || !soil_fmu_in_process(scene)) return nullptr;
  const wire::Envelope e = configure_envelope(scene, config, false);
  try {
    ParticipantSetup setup =
        setup_from_configure(e.configure(), config.participant.role, Newmark::kMaxStepsPerInterval);
    // The scene file is the configuration's source: a relative `file` is
    // found beside it.
    setup.config = OwnConfig::parse(scene.soil_config, scene.source, "soil");
    return std::make_unique<FmuParticipant>(setup);
  } catch (const BadRequestError& b) {
    throw std::invalid_argument(std::string("the soil FMU in process: ") + b.what());
  } catch (const ProtocolError& p) {
    throw std::invalid_argument(std::string("the soil FMU in process: ") + p.what());
  }
}

}  // namespace railcosim::remote
