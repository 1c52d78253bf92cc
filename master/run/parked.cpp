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
  for (const ParticipantSpec& p : specs) {
    owned.push_back(make(subsystem_config(parked, p, o.macro_step, o.tolerance)));
    ps.push_back(owned.back().get());
    roles.push_back(p.role);
    zero.push_back(engine::zero_inputs(parked, p));
  }
  const engine::Routing routing = engine::make_routing(specs);
  const engine::StaticsOutcome statics = engine::find_static_state(ps, routing, zero);
  schedule = engine::make_schedule(spec.scheme, o.feedthrough, o.coupling, ps, routing, roles,
                                   o.macro_step);
  schedule->initialize(statics.inputs);
  for (long n = 0; n < kStart; ++n) schedule->advance(n);
  for (Participant* p : ps) saved.push_back(p->save());
  rest = schedule->memory();
}

}  // namespace railcosim::run
