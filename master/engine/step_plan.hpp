// The step plan: the order in which the participants of a case step over a
// macro step [nH, (n+1)H], and which value each of them takes from each
// peer. plan_steps() is the one place that decides it; the master's
// executor (step_executor.hpp), the direct data plane's links
// (direct_exchange.cpp, obeyed by each node's window runner) and the coupled
// statics (coupled_statics.cpp) all read it from the plan.
//
// The plan is made of stages. The participants of one stage step together
// (their steps are started before any is awaited); a stage steps after the
// ones before it, so a participant takes the outputs at n + 1 of the
// participants of earlier stages and the outputs at n of the others:
//   Jacobi        one stage, every participant in it;
//   Gauss–Seidel  one stage per participant, in load order.
// Resolved feedthrough (Jacobi only): a participant that sends a force is
// refreshed: once its inputs of step n are set, its outputs are read again
// and its receivers take those instead of the ones its last step left.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "cosim_case.hpp"
#include "model.hpp"
#include "participant.hpp"

namespace railcosim::engine {

// Where one input comes from: participant and interface index of the sender.
struct Route {
  int participant = -1;
  int interface = -1;
};
// For participant p and its interface j, routing[p][j] names the sender.
using Routing = std::vector<std::vector<Route>>;

// The routing of a partition: each interface receives what its peer's
// interface on the same cut sends.
Routing make_routing(const std::vector<ParticipantSpec>& participants);

// Which of the sender's values a link's receiver takes for step n.
enum class LinkSource {
  kPoint,      // the outputs at point n, as the sender's last step left them
  kRefreshed,  // the outputs at point n, read again once the sender's own inputs
               // of step n are set (resolved feedthrough)
  kStepped,    // the outputs at point n + 1: the sender steps in an earlier stage
};

// One routed value: receiver p's interface j takes sender q's interface i.
struct PlanLink {
  std::size_t p = 0, j = 0, q = 0, i = 0;
  LinkSource source = LinkSource::kPoint;
  // Implicit coupling: its value at n + 1 is an unknown of the macro step's
  // fixed point (every link whose value at n + 1 is not known when its
  // receiver steps).
  bool iterated = false;
};

struct StepPlan {
  std::vector<PlanLink> links;                   // by receiver, then interface
  std::vector<std::vector<std::size_t>> stages;  // the participants of each stage
  std::vector<std::size_t> stage_of;             // per participant
  std::vector<bool> refreshed;                   // per participant (resolved feedthrough)
  std::vector<std::vector<std::size_t>> into;    // per participant: its links (into `links`)

  std::size_t participants() const { return stage_of.size(); }
  // The link into receiver p from sender q (the first, if several); nullptr if none.
  const PlanLink* between(std::size_t p, std::size_t q) const;
  // The plan as text, one line per stage and per link, the participants
  // named by `roles` (one per participant).
  std::string describe(const std::vector<std::string>& roles) const;
};

// What a plan is made from, besides the routing.
struct PlanOptions {
  Scheme scheme = Scheme::kJacobi;
  Feedthrough feedthrough = Feedthrough::kLagged;
  bool implicit = false;  // implicit coupling: the links' unknowns are iterated
};

// Whether these outputs carry a force on any interface (such a sender is
// refreshed under Jacobi with resolved feedthrough).
bool sends_force(const CouplingData& outputs);

// Throws std::invalid_argument for a combination that does not exist
// (resolved feedthrough under Gauss–Seidel).
void check(const PlanOptions& options);

// THE order of the participants: the plan of a case from its routing, its
// scheme, its feedthrough and which participants send a force (one flag per
// participant, e.g. sends_force() of its outputs at t = 0). Throws
// std::invalid_argument for resolved feedthrough under Gauss–Seidel.
// `leads` (empty, or one flag per participant): participants whose values
// over the step are known before it (a slower participant's view inside
// the faster group of a multirate plan, rate_plan.hpp): they step in a stage
// of their own before every other, their receivers take their values at
// n + 1, and the links into them are never iterated (they take no inputs).
StepPlan plan_steps(const Routing& routing, const PlanOptions& options,
                    const std::vector<bool>& sends_force, const std::vector<bool>& leads = {});

}  // namespace railcosim::engine
