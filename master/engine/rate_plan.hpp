// The rates of a step plan: multirate coupling, where a cut may exchange
// once per window of its own, an integer multiple M of the finest window H.
//
// A participant steps at the finest window among its cuts. Those at H form
// the fast group; the others (at M H) are slow. Over one slow window the
// plan is two-level, and each level is an ordinary step plan (plan_steps()):
//   outer  the fast group, as one participant, and the slow participants,
//          at the slow window M H, by the run's scheme in load order (the
//          group takes the place of its first member);
//   inner  the fast participants at H, M times per slow window, with a view
//          of each slow neighbour: it replays the slow neighbour's values
//          over the slow window as a waveform (held, ramped or the substep
//          waveform the outer level gives the group) and leads every stage,
//          so the fast side takes its values at the end of each fine window.
// The slow side receives the fast side's values over its window as the
// group's samples at each fine window's end. plan_rates() is where the rates
// are ordered; step_plan.hpp orders the participants within a level.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "engine/step_plan.hpp"

namespace railcosim::engine {

struct RatePlan {
  long ratio = 1;                   // M: the slow window in finest windows (1: single rate)
  std::vector<long> window;         // per participant: its window in finest windows (1 or M)
  std::vector<std::size_t> fast;    // the participants at H, in load order
  std::vector<std::size_t> slow;    // the participants at M H, in load order
  std::vector<std::size_t> viewed;  // the slow participants with a fast neighbour (one view each)
  // Per view: the interfaces of its slow participant it shows (those whose
  // peer is fast), in order.
  std::vector<std::vector<std::size_t>> view_interfaces;
  // The fast group's interfaces to the slow side: (member, its interface).
  std::vector<std::pair<std::size_t, std::size_t>> group_interfaces;
  // Inner level: the fast participants (by their index in `fast`), then the
  // views (by their index in `viewed`).
  Routing inner;
  // Outer level: the group and the slow participants, in load order
  // (`outer_members`: the group as fast.front()'s index); `group_at` is the
  // group's position.
  Routing outer;
  std::vector<std::size_t> outer_members;
  std::size_t group_at = 0;

  bool multirate() const { return ratio > 1; }
  // The plan as text: who steps at which window, the views and the group's interfaces.
  std::string describe(const std::vector<std::string>& roles) const;
};

// The rates of a case from its routing and each interface's window in
// finest windows (`windows[p][j]`, that of the cut interface j of
// participant p lies on; both sides of a cut alike). `at_finest` (empty, or
// one flag per participant): participants that step at H whatever their
// cuts' windows (the one holding the vehicle: its moving contact is what H
// resolves). `roles` name the participants in messages. Throws
// std::invalid_argument when:
//   - two cuts have different windows over H (one slow rate in this version);
//   - a cut's window is over H and both its participants step at H;
//   - every participant steps at the slow window (give H the slow window).
RatePlan plan_rates(const Routing& routing, const std::vector<std::vector<long>>& windows,
                    const std::vector<std::string>& roles, const std::vector<bool>& at_finest = {});

}  // namespace railcosim::engine
