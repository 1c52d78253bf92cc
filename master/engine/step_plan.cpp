#include "engine/step_plan.hpp"

#include <sstream>
#include <stdexcept>

namespace railcosim::engine {

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

bool sends_force(const CouplingData& outputs) {
  for (const InterfaceData& d : outputs)
    if (!d.force.empty()) return true;
  return false;
}

void check(const PlanOptions& o) {
  if (o.scheme == Scheme::kGaussSeidel && o.feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved exists only for Jacobi schedules: under Gauss–Seidel, a force "
        "sent at the end of a step necessarily uses the input held over it");
}

StepPlan plan_steps(const Routing& routing, const PlanOptions& o,
                    const std::vector<bool>& sends_force, const std::vector<bool>& leads) {
  check(o);
  const std::size_t P = routing.size();
  if (sends_force.size() != P) throw std::logic_error("plan_steps: one force flag per participant");
  if (!leads.empty() && leads.size() != P)
    throw std::logic_error("plan_steps: one leading flag per participant, or none");
  const auto leading = [&leads](std::size_t p) { return !leads.empty() && leads[p]; };
  StepPlan plan;
  plan.stage_of.assign(P, 0);
  plan.refreshed.assign(P, false);
  // The leading participants first, in a stage of their own.
  for (std::size_t p = 0; p < P; ++p)
    if (leading(p)) {
      if (plan.stages.empty()) plan.stages.emplace_back();
      plan.stages.back().push_back(p);
    }
  const std::size_t first = plan.stages.size();
  // The stages: Jacobi steps every participant at once, Gauss–Seidel one
  // after the other in load order.
  for (std::size_t p = 0; p < P; ++p) {
    if (leading(p)) continue;
    if (o.scheme == Scheme::kJacobi) {
      if (plan.stages.size() == first) plan.stages.emplace_back();
      plan.stages.back().push_back(p);
    } else {
      plan.stages.push_back({p});
    }
    plan.stage_of[p] = plan.stages.size() - 1;
    plan.refreshed[p] = o.feedthrough == Feedthrough::kResolved && sends_force[p];
  }
  plan.into.resize(P);
  for (std::size_t p = 0; p < P; ++p)
    for (std::size_t j = 0; j < routing[p].size(); ++j) {
      const Route& r = routing[p][j];
      PlanLink l;
      l.p = p;
      l.j = j;
      l.q = static_cast<std::size_t>(r.participant);
      l.i = static_cast<std::size_t>(r.interface);
      if (plan.stage_of.at(l.q) < plan.stage_of[p])
        l.source = LinkSource::kStepped;
      else if (plan.refreshed[l.q])
        l.source = LinkSource::kRefreshed;
      l.iterated = o.implicit && l.source != LinkSource::kStepped && !leading(p);
      plan.into[p].push_back(plan.links.size());
      plan.links.push_back(l);
    }
  return plan;
}

const PlanLink* StepPlan::between(std::size_t p, std::size_t q) const {
  for (std::size_t k : into.at(p))
    if (links[k].q == q) return &links[k];
  return nullptr;
}

std::string StepPlan::describe(const std::vector<std::string>& roles) const {
  std::ostringstream s;
  for (std::size_t k = 0; k < stages.size(); ++k) {
    s << "stage " << k + 1 << ":";
    for (std::size_t p : stages[k]) s << ' ' << roles.at(p) << (refreshed[p] ? " (refreshed)" : "");
    s << '\n';
  }
  for (const PlanLink& l : links) {
    s << roles.at(l.p) << '.' << l.j << " <- " << roles.at(l.q) << '.' << l.i << ": ";
    switch (l.source) {
      case LinkSource::kPoint:
        s << "point n";
        break;
      case LinkSource::kRefreshed:
        s << "point n, refreshed";
        break;
      case LinkSource::kStepped:
        s << "point n+1";
        break;
    }
    if (l.iterated) s << ", iterated";
    s << '\n';
  }
  return s.str();
}

}  // namespace railcosim::engine
