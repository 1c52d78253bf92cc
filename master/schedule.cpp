#include "schedule.hpp"

#include <stdexcept>

namespace railcosim {

Routing make_routing(const std::vector<ParticipantSpec>& ps) {
  Routing r(ps.size());
  for (std::size_t p = 0; p < ps.size(); ++p) {
    for (const InterfaceSpec& i : ps[p].interfaces) {
      Route route;
      const auto& peer = ps.at(static_cast<std::size_t>(i.peer));
      for (std::size_t k = 0; k < peer.interfaces.size(); ++k)
        if (peer.interfaces[k].cut == i.cut) route = {i.peer, static_cast<int>(k)};
      if (route.participant < 0)
        throw std::logic_error("make_routing: no peer interface for cut " +
                               std::string(i.kind().name));
      r[p].push_back(route);
    }
  }
  return r;
}

std::vector<StepResult> Schedule::initialize(const std::vector<CouplingData>& inputs) {
  std::vector<StepResult> r;
  for (std::size_t p = 0; p < ps_.size(); ++p) r.push_back(ps_[p]->initialize(inputs[p]));
  keep_outputs(r);
  return r;
}

CouplingData Schedule::inputs_for(std::size_t p) const {
  CouplingData in;
  in.reserve(routing_[p].size());
  for (const Route& r : routing_[p])
    in.push_back(
        out_[static_cast<std::size_t>(r.participant)][static_cast<std::size_t>(r.interface)]);
  return in;
}

void Schedule::keep_outputs(const std::vector<StepResult>& r) {
  out_.resize(r.size());
  for (std::size_t p = 0; p < r.size(); ++p) out_[p] = r[p].outputs;
}

bool sends_force(const CouplingData& outputs) {
  for (const InterfaceData& d : outputs)
    if (!d.force.empty()) return true;
  return false;
}

std::vector<StepResult> JacobiSchedule::advance(long n) {
  const std::size_t P = ps_.size();
  for (std::size_t p = 0; p < P; ++p) ps_[p]->set_inputs(n, inputs_for(p));
  if (feedthrough_ == Feedthrough::kResolved) {
    std::vector<bool> fresh(P, false);
    for (std::size_t p = 0; p < P; ++p)
      if (sends_force(out_[p])) {
        out_[p] = ps_[p]->outputs();
        fresh[p] = true;
      }
    for (std::size_t p = 0; p < P; ++p)
      for (const Route& r : routing_[p])
        if (fresh[static_cast<std::size_t>(r.participant)]) {
          ps_[p]->set_inputs(n, inputs_for(p));
          break;
        }
  }
  for (Participant* p : ps_) p->start_step(n);
  std::vector<StepResult> r;
  r.reserve(P);
  for (Participant* p : ps_) r.push_back(p->finish_step());
  keep_outputs(r);
  return r;
}

std::vector<StepResult> GaussSeidelSchedule::advance(long n) {
  std::vector<StepResult> r;
  r.reserve(ps_.size());
  for (std::size_t p = 0; p < ps_.size(); ++p) {
    ps_[p]->set_inputs(n, inputs_for(p));
    r.push_back(ps_[p]->step(n));
    out_[p] = r.back().outputs;
  }
  return r;
}

std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        std::vector<Participant*> participants, Routing routing) {
  if (scheme == Scheme::kJacobi)
    return std::make_unique<JacobiSchedule>(std::move(participants), std::move(routing),
                                            feedthrough);
  if (feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved exists only for Jacobi schedules: under Gauss–Seidel, a force "
        "sent at the end of a step necessarily uses the input held over it");
  return std::make_unique<GaussSeidelSchedule>(std::move(participants), std::move(routing));
}

}  // namespace railcosim
