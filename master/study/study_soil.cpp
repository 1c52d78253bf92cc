// The study of a scene whose soil is a participant of its own: one the
// study starts itself (the FE soil, the Green's-function soil), as master
// run does, or an external one, which it cannot reach.
#include <algorithm>
#include <stdexcept>

#include "model.hpp"
#include "remote/transport.hpp"
#include "study/study.hpp"

namespace railcosim::study {

std::vector<Method> methods_with_started_soil(const Scene& scene,
                                              const std::vector<Method>& methods) {
  const OutsideSoil* soil = scene.started_soil();
  std::vector<Method> kept;
  for (const Method& m : methods) {
    // Substep waveforms run in process, where a started soil is not.
    if (engine::waveform_degree(m.coupling.inputs) >= 0) continue;
    const bool force_in =
        std::all_of(m.spec.cuts.begin(), m.spec.cuts.end(), [](const CutChoice& c) {
          return cut_kinds()[static_cast<std::size_t>(c.cut)].name != std::string("ss") ||
                 c.coupling == Coupling::kXT;
        });
    if (soil == nullptr || !soil->force_only || force_in) kept.push_back(m);
  }
  if (kept.empty())
    throw std::invalid_argument(scene.source + ": no method of the study reaches " +
                                (soil ? soil->title : "the soil") +
                                " (it takes the ballast force: cases ss-xt-*)");
  return kept;
}

void check_study_scene(const Scene& scene, const StudyOptions& o) {
  if (scene.soil_model == "external" && scene.fmu_mapping("soil").empty())
    throw std::invalid_argument(
        scene.source +
        ": the scene's soil is external (soil.model = \"external\"): a study starts its own "
        "nodes and cannot reach that program; run each case with master run --node "
        "soil=HOST:PORT, or name an FMU in the [soil] table (file = \"soil.fmu\"), which the "
        "study hosts itself");
  if (scene.started_soil() != nullptr && !remote::is_remote_transport(o.transport))
    throw std::invalid_argument(
        scene.source + ": the scene's soil is " + scene.started_soil()->title +
        " (soil.model = \"" + scene.soil_model +
        "\"), a program of its own that the study starts and reaches over TCP: use --transport "
        "tcp (the default), not --transport " +
        o.transport);
}

}  // namespace railcosim::study
