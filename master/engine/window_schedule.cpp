#include "engine/window_schedule.hpp"

#include <stdexcept>

namespace railcosim::engine {

std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        const CouplingOptions& options,
                                        std::vector<Participant*> participants, Routing routing,
                                        std::vector<std::string> roles, double macro_step) {
  if (options.is_plain())
    return make_schedule(scheme, feedthrough, std::move(participants), std::move(routing));
  if (feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved applies to explicit coupling with held inputs only (--coupling "
        "explicit --inputs hold)");
  return std::make_unique<WindowSchedule>(std::move(participants), std::move(routing),
                                          std::move(roles), scheme, options, macro_step);
}

}  // namespace railcosim::engine
