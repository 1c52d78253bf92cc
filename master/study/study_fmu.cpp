// The study of a scene that maps a participant to an FMU (the vehicle's
// [vehicle.fmu], a soil FMU named by [soil]): the methods the FMU can take
// part in, read from its description and its mapping, the rest left out
// with the reason.
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include "log.hpp"
#include "model.hpp"
#include "remote/inproc_fmu.hpp"
#include "study/study.hpp"
#include "subsystem.hpp"

namespace railcosim::study {
namespace {

std::string seconds(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Why the FMUs of `m`'s participants cannot serve it; "" when they can.
std::string fmu_refuses(const Scene& scene, const Method& m) {
  for (const ParticipantSpec& p : partition(scene, m.spec)) {
    std::optional<remote::FmuAbilities> a;
    try {
      a = remote::fmu_abilities(scene,
                                subsystem_config(scene, p, scene.macro_step, scene.tolerance));
    } catch (const std::invalid_argument& e) {
      return "its mapping does not serve this case (" + std::string(e.what()) + ")";
    }
    if (!a) continue;
    const std::string who = "the " + p.role + " FMU";
    if (engine::waveform_degree(m.coupling.inputs) >= 0) return who + " takes no substep waveforms";
    if (m.coupling.inputs != engine::InputMode::kHold && !a->ramps)
      return who + " does not interpolate its inputs (held inputs only, degree 0)";
    if (m.coupling.method == engine::CouplingMethod::kImplicit && !a->state)
      return who + " cannot save its state (explicit coupling only)";
  }
  return "";
}

}  // namespace

std::vector<double> macro_steps_an_fmu_serves(const Scene& scene, const Method& method,
                                              const std::vector<double>& sweep) {
  std::vector<double> kept = sweep;
  for (const ParticipantSpec& p : partition(scene, method.spec)) {
    const auto a =
        remote::fmu_abilities(scene, subsystem_config(scene, p, scene.macro_step, scene.tolerance));
    if (!a || !a->only_step) continue;
    const double step = *a->only_step;
    std::vector<double> same;
    for (double H : kept)
      if (std::abs(H - step) <= 1e-9 * step) same.push_back(H);
    if (same.empty() || std::abs(scene.macro_step - step) > 1e-9 * step)
      throw std::invalid_argument(
          scene.source + ": the " + p.role +
          " FMU cannot vary its communication step "
          "(canHandleVariableCommunicationStepSize is not true) and gives " +
          seconds(step) +
          " s in its default experiment: set simulation.macro_step to it and sweep it alone "
          "(--macro-steps " +
          seconds(step) + ")");
    if (same.size() < kept.size())
      logger("master")->info(
          "study of {}: the {} FMU cannot vary its communication step: the sweep keeps to its "
          "default experiment's {} s",
          scene.source, p.role, seconds(step));
    kept = same;
  }
  return kept;
}

std::vector<Method> methods_an_fmu_serves(const Scene& scene, const std::vector<Method>& methods) {
  std::vector<Method> kept;
  std::map<std::string, std::string> left_out;  // method, why
  for (const Method& m : methods) {
    const std::string why = fmu_refuses(scene, m);
    if (why.empty())
      kept.push_back(m);
    else
      left_out.emplace(m.label(), why);
  }
  auto log = logger("master");
  for (const auto& [label, why] : left_out)
    log->info("study of {}: {} is left out: {}", scene.source, label, why);
  if (kept.empty())
    throw std::invalid_argument(scene.source + ": no method of the study can be run with the " +
                                "scene's FMU: " + left_out.begin()->second);
  return kept;
}

void fit_to_fmus(const Scene& scene, std::vector<Method>& methods, std::vector<double>& sweep) {
  if (scene.fmu_mapping("vehicle").empty() && scene.fmu_mapping("soil").empty()) return;
  methods = methods_an_fmu_serves(scene, methods);
  sweep = macro_steps_an_fmu_serves(scene, methods.front(), sweep);
}

}  // namespace railcosim::study
