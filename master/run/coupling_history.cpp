#include "run/coupling_history.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "track_model.hpp"

namespace railcosim::run {

void record_coupling(RunRecord& run, const std::vector<ParticipantSpec>& participants,
                     const std::vector<StepResult>& outputs) {
  for (std::size_t p = 0; p < participants.size() && p < outputs.size(); ++p) {
    const auto& interfaces = participants[p].interfaces;
    for (std::size_t i = 0; i < interfaces.size() && i < outputs[p].outputs.size(); ++i) {
      const InterfaceSpec& spec = interfaces[i];
      if (spec.kind().moving || spec.side != CutSide::kLower) continue;
      double largest = 0;
      for (double u : outputs[p].outputs[i].displacement) largest = std::max(largest, std::abs(u));
      run.coupling_history[spec.kind().name].push_back(largest);
    }
  }
}

void record_coupling(RunRecord& run, const MonolithicModel& model) {
  const DofLayout& layout = model.structure().layout;
  const auto& u = model.integrator().state().u;
  for (const char* cut : {"rs", "ss"}) {
    if (std::string(cut) == "ss" && layout.soil.empty()) continue;
    double largest = 0;
    for (int d : layer_dofs(layout, find_cut(cut), CutSide::kLower))
      largest = std::max(largest, std::abs(u[d]));
    run.coupling_history[cut].push_back(largest);
  }
}

}  // namespace railcosim::run
