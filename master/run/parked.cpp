#include "run/parked.hpp"

#include <string>

#include "engine/coupled_statics.hpp"
#include "engine/window_schedule.hpp"
#include "subsystem.hpp"

namespace railcosim::run {

ParkedParticipants::ParkedParticipants(const Scene& parked, const CaseSpec& spec,
                                       const RunOptions& o,
                                       const remote::ParticipantFactory& make) {
  const std::vector<ParticipantSpec> specs = partition(parked, spec);
  std::vector<std::string> roles;
  std::vector<CouplingData> zero;
  rates = rate_plan(parked, spec, o);
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const double H = o.macro_step * static_cast<double>(rates.window[k]);
    owned.push_back(make(subsystem_config(parked, specs[k], H, o.tolerance)));
    ps.push_back(owned.back().get());
    roles.push_back(specs[k].role);
    zero.push_back(engine::zero_inputs(parked, specs[k]));
  }
  const engine::Routing routing = engine::make_routing(specs);
  const engine::StaticsOutcome statics = engine::find_static_state(ps, routing, zero);
  schedule = engine::make_coupled_steps(rates, spec.scheme, o.feedthrough, o.coupling, ps, routing,
                                        roles, o.macro_step, statics.inputs);
  schedule->initialize(statics.inputs);
  for (long n = 0; n < kStart; ++n) schedule->advance_map(n);
  for (Participant* p : ps) saved.push_back(p->save());
  rest = schedule->memory();
}

}  // namespace railcosim::run
