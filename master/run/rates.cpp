// The rates of a run (runner.hpp: rate_plan()): each interface's window
// from its cut's, then engine::plan_rates().
#include <cmath>
#include <stdexcept>

#include "engine/step_plan.hpp"
#include "run/runner.hpp"

namespace railcosim::run {

engine::RatePlan rate_plan(const Scene& scene, const CaseSpec& spec, const RunOptions& o) {
  const std::vector<ParticipantSpec> specs = partition(scene, spec);
  std::vector<std::vector<long>> windows;
  std::vector<std::string> roles;
  std::vector<bool> vehicle;  // steps at H: its moving contact is what H resolves
  for (const ParticipantSpec& p : specs) {
    roles.push_back(p.role);
    vehicle.push_back(p.parts.has(Component::kVehicle));
    windows.emplace_back();
    for (const InterfaceSpec& i : p.interfaces) {
      const auto w = o.cut_windows.find(i.kind().name);
      windows.back().push_back(w == o.cut_windows.end() ? 1 : w->second);
    }
  }
  engine::RatePlan r = engine::plan_rates(engine::make_routing(specs), windows, roles, vehicle);
  if (!r.multirate()) return r;
  if (o.feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved reads a sender's outputs within its step: a cut at a window of "
        "its own has none to read; use lagged feedthrough");
  return r;
}

double participant_step(const Scene& scene, const CaseSpec& spec, const RunOptions& o,
                        const std::string& role) {
  if (spec.monolithic) return o.macro_step;
  const std::vector<ParticipantSpec> specs = partition(scene, spec);
  const engine::RatePlan r = rate_plan(scene, spec, o);
  for (std::size_t k = 0; k < specs.size(); ++k)
    if (specs[k].role == role) return o.macro_step * static_cast<double>(r.window[k]);
  return o.macro_step;
}

void check_whole_windows(const Scene& scene, const RunOptions& o, const engine::RatePlan& r) {
  const long N = std::lround(scene.end_time / o.macro_step);
  if (N % r.ratio != 0)
    throw std::invalid_argument(
        "the end time " + std::to_string(scene.end_time) + " s of " + scene.source + " is " +
        std::to_string(N) + " finest windows, not a whole number of the slow window (" +
        std::to_string(r.ratio) + " H): change simulation.end_time or the cut's window");
}

}  // namespace railcosim::run
