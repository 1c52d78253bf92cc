// The direct data plane's master side: who holds a macro step up. Progress
// frames move the deadline on only when they advance, and only a node's own;
// a node's claim to wait for a peer is checked against its links, and a
// peer's step reports are not taken for the data it sends.
#include <algorithm>
#include <sstream>

#include "remote/direct_exchange.hpp"

namespace railcosim::remote {

using std::chrono::milliseconds;

void DirectExchange::take_progress(Node& node, const wire::Envelope& e) {
  const wire::Progress& p = e.progress();
  if (p.step() < node.reported || p.step() >= window_end_)
    node.p->fail_at(node.reported, "bad reply: a progress frame for macro step " +
                                       std::to_string(p.step()) + ", outside [" +
                                       std::to_string(node.reported) + ", " +
                                       std::to_string(window_end_) + ")");
  if (p.step() > node.progress_step ||
      (p.step() == node.progress_step && p.micro_steps() > node.progress_micro)) {
    node.progress_step = static_cast<long>(p.step());
    node.progress_micro = p.micro_steps();
    ++node.counted_progress;
    node.stale_progress = 0;
    node.last_useful = std::chrono::steady_clock::now();
  } else {
    ++node.stale_progress;
  }
}

std::chrono::steady_clock::time_point DirectExchange::last_useful() const {
  std::chrono::steady_clock::time_point last{}, any{};
  for (const Node& node : nodes_) {
    any = std::max(any, node.last_useful);
    if (node.reports.empty()) last = std::max(last, node.last_useful);
  }
  return last == std::chrono::steady_clock::time_point{} ? any : last;
}

namespace {

// The node `claimant` says it waits for, if that is a peer of its: -1 none
// claimed, -2 a claim the master knows is false.
long claimed_node(const std::vector<HoldUp>& nodes, std::size_t claimant) {
  const HoldUp& c = nodes[claimant];
  if (c.waiting_for.empty()) return -1;
  if (std::find(c.peers.begin(), c.peers.end(), c.waiting_for) == c.peers.end()) return -2;
  for (std::size_t k = 0; k < nodes.size(); ++k)
    if (k != claimant && nodes[k].role == c.waiting_for) return static_cast<long>(k);
  return -2;
}

}  // namespace

Blamed blame(const std::vector<HoldUp>& nodes) {
  const std::size_t P = nodes.size();
  std::vector<long> to(P);
  for (std::size_t k = 0; k < P; ++k) to[k] = claimed_node(nodes, k);
  // A claim the master knows is false.
  for (std::size_t k = 0; k < P; ++k)
    if (to[k] == -2) {
      const HoldUp& c = nodes[k];
      bool known = false;
      for (const HoldUp& x : nodes) known = known || (x.role == c.waiting_for && &x != &c);
      return {k, "; it says it waits for the " + c.waiting_for + " participant, " +
                     (known ? std::string("with which it has no peer link")
                            : std::string("which is not a participant of this run"))};
    }
  // The claims believed, followed from the earliest: to a node that claims
  // nothing, or round a cycle.
  std::vector<std::size_t> claimants;
  for (std::size_t k = 0; k < P; ++k)
    if (to[k] >= 0) claimants.push_back(k);
  std::stable_sort(claimants.begin(), claimants.end(), [&](std::size_t a, std::size_t b) {
    return nodes[a].claimed_at < nodes[b].claimed_at;
  });
  if (!claimants.empty()) {
    std::vector<bool> seen(P, false);
    std::vector<std::size_t> path;
    std::size_t at = claimants.front();
    while (!seen[at] && to[at] >= 0) {
      seen[at] = true;
      path.push_back(at);
      at = static_cast<std::size_t>(to[at]);
    }
    if (to[at] < 0) return {at, ""};  // it waits for nobody
    // Round a cycle (from `at`): the one whose reports went furthest, the
    // first claim's peer on a tie.
    const auto begin = std::find(path.begin(), path.end(), at);
    std::size_t worst = static_cast<std::size_t>(to[claimants.front()]);
    if (std::find(begin, path.end(), worst) == path.end()) worst = at;
    for (auto k = begin; k != path.end(); ++k)
      if (nodes[*k].reported > nodes[worst].reported) worst = *k;
    return {worst, ""};
  }
  // No claim: of those that have not reported the step, the one that
  // reported least, then the one silent longest.
  std::size_t slow = P;
  for (std::size_t k = 0; k < P; ++k) {
    if (nodes[k].has_step) continue;
    if (slow == P || nodes[k].reported < nodes[slow].reported ||
        (nodes[k].reported == nodes[slow].reported &&
         nodes[k].last_useful < nodes[slow].last_useful))
      slow = k;
  }
  return {slow == P ? 0 : slow, ""};
}

void DirectExchange::silence(long n, milliseconds waited, bool budget) {
  std::vector<HoldUp> facts;
  for (const Node& node : nodes_)
    facts.push_back({node.p->role(), node.peers, node.reported, !node.reports.empty(),
                     node.waiting_for, node.claimed_at, node.last_useful});
  const Blamed blamed = blame(facts);
  Node* slow = &nodes_[blamed.node];
  const std::string& claim = blamed.claim;
  std::string waiters;
  for (const Node& other : nodes_)
    if (&other != slow && other.waiting_for == slow->p->role() &&
        std::find(other.peers.begin(), other.peers.end(), slow->p->role()) != other.peers.end())
      waiters += (waiters.empty() ? "" : ", ") + other.p->role();
  std::ostringstream s;
  if (budget)
    s << budget_text(waited);
  else if (!slow->reports.empty())  // it has reported the step: what it owes is data
    s << "no data to its peers within " << waited.count() << " ms";
  else if (slow->counted_progress > 0 || slow->stale_progress > 0)
    s << "no progress for " << waited.count() << " ms";
  else
    s << "no reply within " << waited.count() << " ms";
  // The failure names macro step n: the last report is said only where it
  // differs.
  if (slow->reported != n)
    s << " (its last step report was for macro step " << slow->reported << claim;
  else
    s << " (its step reports reached this macro step" << claim;
  if (slow->counted_progress > 0)
    s << "; its last progress frame that counted was at micro step " << slow->progress_micro
      << " of macro step " << slow->progress_step;
  if (slow->stale_progress > 0)
    s << "; " << slow->stale_progress << " progress frame(s) since then did not advance";
  // A node that keeps its stream busy without reporting a step.
  if (slow->idle_frames > 0)
    s << "; since then it sent " << slow->idle_frames << " report frame(s) without a step report";
  if (const std::size_t part = slow->p->tcp()->partial_bytes(); part > 0)
    s << "; it has sent " << part << " byte(s) of a frame it has not finished";
  if (!waiters.empty()) s << "; the " << waiters << " participant(s) wait for its data";
  // Its step reports are its word, not the data its peers wait for.
  if (!waiters.empty() && !slow->reports.empty())
    s << ": its step reports are no proof it sent them";
  s << ")";
  slow->p->fail_at(n, s.str());
}

}  // namespace railcosim::remote
