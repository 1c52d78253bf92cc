// The direct data plane's master side: who holds a macro step up. Progress
// frames move the deadline on only when they advance; a node's claim to wait
// for a peer is checked against the peer's own reports before anyone is
// blamed.
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
    last_useful_ = std::chrono::steady_clock::now();
  } else {
    ++node.stale_progress;
  }
}

const DirectExchange::Node* DirectExchange::claimed(const Node& claimant) const {
  if (claimant.waiting_for.empty()) return nullptr;
  for (const Node& peer : nodes_)
    if (&peer != &claimant && peer.p->role() == claimant.waiting_for) return &peer;
  return nullptr;
}

DirectExchange::Node* DirectExchange::false_claimant() {
  // A peer that has reported past the claimant's point has sent everything
  // the claimant's next step needs (a node sends its outputs at a point
  // before it reports reaching it): the claim is false, and so is one that
  // names no participant of the run.
  for (Node& node : nodes_) {
    if (node.waiting_for.empty()) continue;
    const Node* peer = claimed(node);
    if (!peer || peer->reported > node.reported) return &node;
  }
  return nullptr;
}

void DirectExchange::silence(long n, milliseconds waited, bool budget) {
  // A node that claims to wait for a peer the master knows has sent its data
  // is to blame; else the node that others wait for and that waits for
  // nobody hangs; else the one that reported least.
  Node* slow = false_claimant();
  std::string claim;
  if (slow) {
    const Node* peer = claimed(*slow);
    claim = "; it says it waits for the " + slow->waiting_for + " participant, " +
            (peer ? "whose step reports reached macro step " + std::to_string(peer->reported)
                  : std::string("which is not a participant of this run"));
  }
  for (Node& node : nodes_)
    if (!slow && node.waiting_for.empty())
      for (const Node& other : nodes_)
        if (claimed(other) == &node && !slow) slow = &node;
  if (!slow) {
    slow = &nodes_.front();
    for (Node& node : nodes_)
      if (node.reported < slow->reported) slow = &node;
  }
  std::string waiters;
  for (const Node& other : nodes_)
    if (claimed(other) == slow && other.reported >= slow->reported)
      waiters += (waiters.empty() ? "" : ", ") + other.p->role();
  std::ostringstream s;
  if (budget)
    s << budget_text(waited);
  else if (slow->counted_progress > 0 || slow->stale_progress > 0)
    s << "no progress for " << waited.count() << " ms";
  else
    s << "no reply within " << waited.count() << " ms";
  s << " (its last step report was for macro step " << slow->reported << claim;
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
  s << ")";
  slow->p->fail_at(n, s.str());
}

}  // namespace railcosim::remote
