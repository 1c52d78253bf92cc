#include "engine/rate_plan.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace railcosim::engine {
namespace {

std::size_t index_in(const std::vector<std::size_t>& v, std::size_t x) {
  return static_cast<std::size_t>(std::find(v.begin(), v.end(), x) - v.begin());
}

// Each participant's window, checked: one slow rate, a slow cut with a slow side.
void assign_windows(RatePlan& r, const Routing& routing,
                    const std::vector<std::vector<long>>& windows,
                    const std::vector<std::string>& roles, const std::vector<bool>& at_finest) {
  const std::size_t P = routing.size();
  for (std::size_t p = 0; p < P; ++p) {
    if (windows.at(p).size() != routing[p].size())
      throw std::logic_error("plan_rates: one window per interface");
    long w = 0;
    for (long x : windows[p]) {
      if (x < 1) throw std::logic_error("plan_rates: a window of at least one finest window");
      w = w == 0 ? x : std::min(w, x);
      if (x > 1 && r.ratio > 1 && x != r.ratio)
        throw std::invalid_argument(
            "cuts at " + std::to_string(r.ratio) + " and " + std::to_string(x) +
            " finest windows: this version couples one slower window besides the finest H; give "
            "the coarser cuts the same window");
      if (x > 1) r.ratio = x;
    }
    r.window.push_back(!at_finest.empty() && at_finest.at(p) ? 1 : w);
  }
  for (std::size_t p = 0; p < P; ++p)
    for (std::size_t j = 0; j < routing[p].size(); ++j) {
      const auto q = static_cast<std::size_t>(routing[p][j].participant);
      if (windows[p][j] > 1 && r.window[p] == 1 && r.window[q] == 1)
        throw std::invalid_argument(
            "a cut between " + roles.at(p) + " and " + roles.at(q) + " at " +
            std::to_string(windows[p][j]) +
            " finest windows: both participants step at the finest window (a cut there, or the "
            "vehicle), so neither could step at the coarser one; split the case so that one "
            "side holds only coarser cuts, or leave the cut at H");
    }
  for (std::size_t p = 0; p < P; ++p) (r.window[p] == 1 ? r.fast : r.slow).push_back(p);
  if (r.multirate() && r.fast.empty())
    throw std::invalid_argument("every cut at " + std::to_string(r.ratio) +
                                " finest windows: nothing steps at H; give H that window instead");
}

void route_inner(RatePlan& r, const Routing& routing) {
  const std::size_t F = r.fast.size();
  for (std::size_t s : r.slow) {
    std::vector<std::size_t> shown;
    for (std::size_t i = 0; i < routing[s].size(); ++i)
      if (r.window[static_cast<std::size_t>(routing[s][i].participant)] == 1) shown.push_back(i);
    if (shown.empty()) continue;
    r.viewed.push_back(s);
    r.view_interfaces.push_back(shown);
  }
  r.inner.assign(F + r.viewed.size(), {});
  for (std::size_t a = 0; a < F; ++a)
    for (std::size_t j = 0; j < routing[r.fast[a]].size(); ++j) {
      const Route& to = routing[r.fast[a]][j];
      const auto q = static_cast<std::size_t>(to.participant);
      if (r.window[q] == 1) {
        r.inner[a].push_back({static_cast<int>(index_in(r.fast, q)), to.interface});
        continue;
      }
      const std::size_t v = index_in(r.viewed, q);
      const std::size_t at = index_in(r.view_interfaces[v], static_cast<std::size_t>(to.interface));
      r.inner[a].push_back({static_cast<int>(F + v), static_cast<int>(at)});
      r.group_interfaces.emplace_back(a, j);
    }
  for (std::size_t v = 0; v < r.viewed.size(); ++v)
    for (std::size_t i : r.view_interfaces[v]) {
      const Route& to = routing[r.viewed[v]][i];
      r.inner[F + v].push_back(
          {static_cast<int>(index_in(r.fast, static_cast<std::size_t>(to.participant))),
           to.interface});
    }
}

void route_outer(RatePlan& r, const Routing& routing) {
  for (std::size_t p = 0; p < routing.size(); ++p) {
    if (r.window[p] == 1 && p != r.fast.front()) continue;
    if (p == r.fast.front()) r.group_at = r.outer_members.size();
    r.outer_members.push_back(p);
  }
  auto outer_of = [&r](std::size_t p) {
    return static_cast<int>(r.window[p] == 1 ? r.group_at : index_in(r.outer_members, p));
  };
  r.outer.assign(r.outer_members.size(), {});
  for (const auto& [a, j] : r.group_interfaces) {
    const Route& to = routing[r.fast[a]][j];
    r.outer[r.group_at].push_back(
        {outer_of(static_cast<std::size_t>(to.participant)), to.interface});
  }
  for (std::size_t s : r.slow)
    for (const Route& to : routing[s]) {
      const auto q = static_cast<std::size_t>(to.participant);
      if (r.window[q] > 1) {
        r.outer[static_cast<std::size_t>(outer_of(s))].push_back({outer_of(q), to.interface});
        continue;
      }
      const std::pair<std::size_t, std::size_t> member{index_in(r.fast, q),
                                                       static_cast<std::size_t>(to.interface)};
      const auto k = std::find(r.group_interfaces.begin(), r.group_interfaces.end(), member) -
                     r.group_interfaces.begin();
      r.outer[static_cast<std::size_t>(outer_of(s))].push_back(
          {static_cast<int>(r.group_at), static_cast<int>(k)});
    }
}

}  // namespace

RatePlan plan_rates(const Routing& routing, const std::vector<std::vector<long>>& windows,
                    const std::vector<std::string>& roles, const std::vector<bool>& at_finest) {
  RatePlan r;
  assign_windows(r, routing, windows, roles, at_finest);
  if (!r.multirate()) return r;
  route_inner(r, routing);
  route_outer(r, routing);
  return r;
}

std::string RatePlan::describe(const std::vector<std::string>& roles) const {
  std::ostringstream s;
  s << "at H:";
  for (std::size_t p : fast) s << ' ' << roles.at(p);
  s << "\nat " << ratio << " H:";
  for (std::size_t p : slow) s << ' ' << roles.at(p);
  s << "\nviews inside the group:";
  for (std::size_t v = 0; v < viewed.size(); ++v) {
    s << ' ' << roles.at(viewed[v]) << " (interfaces";
    for (std::size_t i : view_interfaces[v]) s << ' ' << i;
    s << ')';
  }
  s << "\nthe group's interfaces:";
  for (const auto& [a, j] : group_interfaces) s << ' ' << roles.at(fast[a]) << '.' << j;
  s << '\n';
  return s.str();
}

}  // namespace railcosim::engine
