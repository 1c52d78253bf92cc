#include "cli/conform_statics.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "cosim_case.hpp"
#include "engine/coupled_statics.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "subsystem.hpp"

namespace railcosim::cli {

std::string check_soil_statics(const Scene& scene, const ConformOptions& o) {
  if (o.role != "soil") return "skipped: the check is of a soil's statics";
  const std::vector<ParticipantSpec> specs = partition(scene, parse_case(o.case_name));
  const remote::ParticipantFactory local = remote::inproc_factory(scene);
  remote::RemoteTimeouts t;
  t.reply = t.step_min = t.step_max = std::chrono::milliseconds(10000);
  std::vector<std::unique_ptr<Participant>> owned;
  std::vector<Participant*> ps;
  std::size_t soil = specs.size();
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const SubsystemConfig c = subsystem_config(scene, specs[k], scene.macro_step, scene.tolerance);
    if (specs[k].role == o.role) {
      soil = k;
      owned.push_back(std::make_unique<remote::RemoteParticipant>(o.address, scene, c, t, o.token));
    } else {
      owned.push_back(local(c));
    }
    ps.push_back(owned.back().get());
  }
  if (soil == specs.size()) return "skipped: case " + o.case_name + " has no soil participant";
  std::vector<CouplingData> zero;
  for (const ParticipantSpec& p : specs) zero.push_back(engine::zero_inputs(scene, p));
  const engine::StaticsOutcome state =
      engine::find_static_state(ps, engine::make_routing(specs), zero);
  double sum = 0;  // Σ s_i, m, positive down
  for (const InterfaceData& d : ps[soil]->statics(state.inputs[soil]))
    for (double s : d.displacement) sum += s;
  const double weight = scene.load();
  std::ostringstream why;
  why.precision(6);
  if (scene.builtin_soil()) {
    const double carried = scene.soil_stiffness * sum;
    if (std::isfinite(carried) && std::abs(carried - weight) <= kStaticsTolerance * weight)
      return "";
    why << "at the coupled static state the soil springs carry k_f Σ s_i = " << carried
        << " N, the vehicle's weight m·g is " << weight << " N (relative tolerance "
        << kStaticsTolerance << "; k_f = " << scene.soil_stiffness
        << " N/m, the scene's [soil] stiffness; s_i positive down)";
    if (carried < 0) why << ": the soil rises under the load, the sign of its statics is wrong";
    return why.str();
  }
  if (std::isfinite(sum) && sum > 0) return "";
  why << "at the coupled static state the soil's displacements sum to " << sum
      << " m (positive down): under the vehicle's weight of " << weight
      << " N it must sink, the sign of its statics is wrong";
  return why.str();
}

}  // namespace railcosim::cli
