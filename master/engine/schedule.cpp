#include "engine/schedule.hpp"

namespace railcosim::engine {

std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        std::vector<Participant*> participants, Routing routing) {
  if (scheme == Scheme::kJacobi)
    return std::make_unique<JacobiSchedule>(std::move(participants), std::move(routing),
                                            feedthrough);
  check(PlanOptions{scheme, feedthrough, false});
  return std::make_unique<GaussSeidelSchedule>(std::move(participants), std::move(routing));
}

}  // namespace railcosim::engine
