#include "remote/direct_exchange.hpp"

#include <functional>

#include <poll.h>

#include <algorithm>
#include <sstream>

#include "auth.hpp"
#include "remote/peer_text.hpp"

namespace railcosim::remote {

using std::chrono::milliseconds;

bool enter_lockstep(const std::vector<Participant*>& ps, long first, long end) {
  std::vector<RemoteParticipant*> nodes;
  for (Participant* p : ps) {
    auto* r = dynamic_cast<RemoteParticipant*>(p);
    if (!r || !r->lockstep_capable()) return false;
    nodes.push_back(r);
  }
  for (RemoteParticipant* r : nodes) r->enter_lockstep(first, end);
  return true;
}

std::string relay_reason(const std::vector<Participant*>& ps, bool lockstep) {
  std::string lacking;
  for (Participant* p : ps) {
    auto* r = dynamic_cast<RemoteParticipant*>(p);
    if (r && (lockstep ? r->lockstep_capable() : r->direct_capable())) continue;
    lacking += lacking.empty() ? "" : ", ";
    lacking += r ? r->name() : p->name();
  }
  if (lacking.empty()) return "";
  return lockstep ? "the lock step, which implicit coupling and ramped inputs need on the direct "
                    "plane, is not offered by " +
                        lacking
                  : "the direct plane's windows are not offered by " + lacking;
}

std::unique_ptr<DirectExchange> DirectExchange::make(const std::vector<Participant*>& ps,
                                                     const engine::StepPlan& plan, double bound,
                                                     long total, DirectOptions options) {
  std::vector<RemoteParticipant*> nodes;
  for (Participant* p : ps) {
    auto* r = dynamic_cast<RemoteParticipant*>(p);
    if (!r || !r->direct_capable()) return nullptr;
    // Peer links and the polling of several nodes at once are TCP's.
    if (!r->tcp())
      throw NodeFailure(r->name() +
                        ": the direct data plane needs a TCP connection to the node, and this "
                        "one is another channel: use --data-plane relay");
    nodes.push_back(r);
  }
  const std::size_t P = nodes.size();
  const std::string session = random_nonce();
  const auto& t = nodes.front()->timeouts();
  // A node waits for a peer longer than the master waits for any node, so
  // that the master, which sees every node, names the one that fell silent.
  const auto link_timeout = std::max(t.step_max, t.step_budget) + t.reply;
  std::vector<wire::Links> links(P);
  for (std::size_t p = 0; p < P; ++p) {
    links[p].set_session(session);
    links[p].set_refresh(plan.refreshed[p]);
    links[p].set_timeout_ms(static_cast<std::uint32_t>(link_timeout.count()));
  }
  // One link per pair of participants that share a cut; the one loaded first
  // connects. Both ends list their interfaces in the same order. What each
  // end waits for is the plan's: the peer's data at n + 1 where the peer
  // steps in an earlier stage (ahead), its second sending where the peer is
  // refreshed.
  for (std::size_t p = 0; p < P; ++p)
    for (std::size_t q = p + 1; q < P; ++q) {
      const engine::PlanLink* from_q = plan.between(p, q);
      const engine::PlanLink* from_p = plan.between(q, p);
      if (!from_q || !from_p) continue;
      wire::PeerLink* mine = links[p].add_links();
      mine->set_peer(nodes[q]->role());
      mine->set_host(nodes[q]->address().host);
      mine->set_port(nodes[q]->address().port);
      mine->set_ahead(from_q->source == engine::LinkSource::kStepped);
      mine->set_refreshes(from_q->source == engine::LinkSource::kRefreshed);
      wire::PeerLink* theirs = links[q].add_links();
      theirs->set_peer(nodes[p]->role());
      theirs->set_ahead(from_p->source == engine::LinkSource::kStepped);
      theirs->set_refreshes(from_p->source == engine::LinkSource::kRefreshed);
      for (std::size_t k : plan.into[p])
        if (plan.links[k].q == q) {
          mine->add_interfaces(static_cast<int>(plan.links[k].j));
          theirs->add_interfaces(static_cast<int>(plan.links[k].i));
        }
    }
  for (std::size_t p = 0; p < P; ++p) nodes[p]->set_links(links[p]);
  std::unique_ptr<DirectExchange> x(new DirectExchange(nodes, bound, total, options));
  for (std::size_t p = 0; p < P; ++p)
    for (const wire::PeerLink& l : links[p].links()) x->nodes_[p].peers.push_back(l.peer());
  return x;
}

DirectExchange::DirectExchange(std::vector<RemoteParticipant*> nodes, double bound, long total,
                               DirectOptions options)
    : bound_(bound), total_(total), options_(options) {
  for (RemoteParticipant* p : nodes) {
    nodes_.emplace_back();
    nodes_.back().p = p;
  }
}

DirectExchange::~DirectExchange() {
  for (Node& node : nodes_)
    if (node.in_window && !node.closed) node.p->tcp()->close();
}

void DirectExchange::grant(long n) {
  const long end = options_.window_steps > 0 ? std::min(total_, n + options_.window_steps) : total_;
  wire::Window w;
  w.set_first_step(n);
  w.set_end_step(end);
  window_end_ = end;
  w.set_divergence_bound(bound_);
  w.set_report_steps(options_.report_steps);
  const auto now = std::chrono::steady_clock::now();
  for (Node& node : nodes_) {
    node.last_useful = now;
    node.p->grant(w);
    node.in_window = true;
    node.done_step = -1;
    node.done_reason.clear();
    node.progress_step = -1;
    node.progress_micro = 0;
    node.counted_progress = node.stale_progress = 0;
  }
}

std::chrono::milliseconds DirectExchange::progress() const {
  const RemoteTimeouts& t = nodes_.front().p->timeouts();
  if (slowest_gap_.count() == 0) return t.step_max;
  const auto scaled = std::chrono::duration_cast<milliseconds>(
      std::chrono::duration<double>(slowest_gap_) * t.step_factor);
  return std::clamp(scaled, t.step_min, t.step_max);
}

void DirectExchange::take(Node& node, const wire::Envelope& e) {
  if (e.has_progress()) {
    take_progress(node, e);
    return;
  }
  // The time per step, as the relayed plane measures a step's reply.
  const auto now = std::chrono::steady_clock::now();
  if (e.has_reports() && e.reports().reports_size() > 0) {
    if (node.last_frame != std::chrono::steady_clock::time_point{})
      slowest_gap_ = std::max(slowest_gap_, (now - node.last_frame) / e.reports().reports_size());
    node.last_frame = now;
    node.idle_frames = 0;
    node.counted_progress = node.stale_progress = 0;
    node.last_useful = now;
  } else if (e.has_reports()) {
    ++node.idle_frames;
  } else {
    node.last_useful = now;
  }
  if (e.has_reports()) {
    node.p->accept_reports_frame(e.id());
    std::string claim = terminal_text(e.reports().waiting_for());
    if (!claim.empty() && claim != node.waiting_for) node.claimed_at = now;
    node.waiting_for = std::move(claim);
    for (const auto& w : e.reports().reports()) {
      node.reports.push_back(node.p->accept_report(w));
      node.reported = static_cast<long>(w.step());
    }
    return;
  }
  node.in_window = false;
  try {
    node.p->window_reply(e);
    node.done_step = static_cast<long>(e.window_done().step());
    node.done_reason = terminal_text(e.window_done().reason());
  } catch (const StepFailure& f) {
    node.failed = true;
    node.step_failure = true;
    node.fail_step = e.error().step();
    node.fail_text = f.what();
  } catch (const NodeFailure& f) {
    node.failed = true;
    node.fail_step = e.has_error() && e.error().step() >= 0 ? e.error().step() : node.reported;
    node.fail_text = f.what();
    node.peer_failed = e.has_error() && e.error().code() == wire::Error::PEER_FAILED;
    // The peer whose data (or frames) it refused: the root cause.
    if (node.peer_failed)
      for (std::size_t k = 0; k < nodes_.size(); ++k)
        if (&nodes_[k] != &node && nodes_[k].p->role() == e.error().sender())
          node.sender = static_cast<int>(k);
  }
}

bool DirectExchange::read(milliseconds timeout) {
  std::vector<pollfd> fds;
  std::vector<Node*> who;
  for (Node& node : nodes_)
    if (node.in_window && !node.closed) {
      fds.push_back(pollfd{node.p->tcp()->fd(), POLLIN, 0});
      who.push_back(&node);
    }
  if (fds.empty()) return true;
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (const int sig = interrupt_signal()) {
      std::ostringstream s;
      s << "interrupted by signal " << sig << " at macro step " << step_
        << " (t = " << static_cast<double>(step_) * nodes_.front().p->macro_step() << " s)";
      throw std::runtime_error(s.str());
    }
    const auto left = std::chrono::ceil<milliseconds>(until - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    if (::poll(fds.data(), fds.size(), static_cast<int>(std::min(left, kInterruptPoll).count())) >
        0)
      break;
  }
  for (std::size_t k = 0; k < fds.size(); ++k) {
    if (fds[k].revents == 0) continue;
    Node& node = *who[k];
    Connection& c = *node.p->tcp();
    bool open = true;
    try {
      open = c.read_now();
      wire::Envelope e;
      while (node.in_window && c.next_buffered(e)) take(node, e);
    } catch (const NetError& e) {
      open = false;
      node.fail_text = e.what();
    } catch (const NodeFailure& e) {
      node.failed = true;
      node.fail_step = node.reported;
      node.fail_text = e.what();
      node.in_window = false;
    }
    if (!open && node.in_window) {
      node.closed = true;
      node.in_window = false;
      node.failed = true;
      node.fail_step = node.reported;
      std::string what = "the node closed the connection in the middle of a window";
      if (!node.fail_text.empty()) what += " (" + node.fail_text + ")";
      // "at macro step N" below is its last step report's: said once.
      node.fail_text = node.p->failure_text(node.reported, what);
    }
  }
  return true;
}

std::vector<StepResult> DirectExchange::advance(long n) {
  step_ = n;
  const auto waiting_since = std::chrono::steady_clock::now();
  while (true) {
    bool ready = true;
    for (const Node& node : nodes_) ready = ready && !node.reports.empty();
    if (ready) {
      std::vector<StepResult> out;
      out.reserve(nodes_.size());
      for (Node& node : nodes_) {
        out.push_back(std::move(node.reports.front()));
        node.reports.pop_front();
      }
      return out;
    }
    if (const Node* f = culprit(n, false)) {
      fail_with(*f);
      continue;
    }
    bool any_in_window = false;
    for (const Node& node : nodes_) any_in_window = any_in_window || node.in_window;
    if (!any_in_window) {
      // Nothing more can come from a node that failed, whatever its step.
      if (const Node* f = culprit(n, true)) {
        fail_with(*f);
        continue;
      }
      check_window_end(n);
      grant(n);
      continue;
    }
    // One deadline for the next step report, however the node's bytes come.
    // And one for the whole step, however much progress the nodes show.
    const milliseconds limit = progress();
    const milliseconds budget = nodes_.front().p->timeouts().step_budget;
    const auto now = std::chrono::steady_clock::now();
    const auto deadline = std::max(last_useful(), waiting_since) + limit;
    if (now >= waiting_since + budget) silence(n, budget, true);
    if (now >= deadline) silence(n, limit);
    read(std::chrono::ceil<milliseconds>(std::min(deadline, waiting_since + budget) - now));
  }
}

namespace {

// Lower is nearer the root cause.
int rank(bool step_failure, int sender, bool closed, bool peer_failed) {
  if (step_failure || sender >= 0) return 0;
  if (closed) return 1;
  return peer_failed ? 3 : 2;
}

}  // namespace

const DirectExchange::Node* DirectExchange::culprit(long n, bool any_step) const {
  bool due = false;
  for (const Node& node : nodes_)
    due = due || (node.failed && (any_step || node.fail_step <= n || node.reports.empty()));
  if (!due) return nullptr;
  const Node* best = nullptr;
  int best_rank = 4;
  for (const Node& node : nodes_) {
    if (!node.failed) continue;
    const int r = rank(node.step_failure, node.sender, node.closed, node.peer_failed);
    if (r < best_rank) {
      best = &node;
      best_rank = r;
    }
  }
  return best;
}

void DirectExchange::fail_with(const Node& node) {
  if (node.step_failure) throw StepFailure(node.fail_text);
  if (node.sender >= 0) {
    const Node& from = nodes_[static_cast<std::size_t>(node.sender)];
    throw NodeFailure(from.p->failure_text(
        node.fail_step,
        "the " + node.p->role() + " participant refused its data (" + node.fail_text + ")"));
  }
  if (!node.peer_failed) throw NodeFailure(node.fail_text);
  const auto now = std::chrono::steady_clock::now();
  if (first_peer_failure_ == std::chrono::steady_clock::time_point{}) first_peer_failure_ = now;
  const auto left =
      milliseconds(1000) - std::chrono::duration_cast<milliseconds>(now - first_peer_failure_);
  bool open = false;
  for (const Node& x : nodes_) open = open || (x.in_window && !x.closed);
  if (left.count() <= 0 || !open) throw NodeFailure(node.fail_text);
  read(left);  // the culprit's own failure, if it comes, is preferred next time
}

void DirectExchange::check_window_end(long n) {
  if (window_end_ < 0) return;
  // A node whose reports stop short of where it says its window ended.
  for (Node& node : nodes_)
    if (node.reports.empty() && node.reported < node.done_step)
      node.p->fail_at(n, "its window ended at macro step " + std::to_string(node.done_step) +
                             ", but its step reports stop at macro step " +
                             std::to_string(node.reported));
  for (Node& node : nodes_)
    if (node.reports.empty() && !node.done_reason.empty())
      node.p->fail_at(
          n, "stopped at macro step " + std::to_string(node.done_step) + ": " + node.done_reason);
  for (Node& node : nodes_)
    if (node.reports.empty() && (node.done_step != window_end_ || n != window_end_))
      node.p->fail_at(n, "ended its window at macro step " + std::to_string(node.done_step) +
                             ", before the window's end at macro step " +
                             std::to_string(window_end_) + ", without saying why");
}

void DirectExchange::drain() {
  const auto deadline = std::chrono::steady_clock::now() + milliseconds(5000);
  while (std::chrono::steady_clock::now() < deadline) {
    bool any = false;
    for (const Node& node : nodes_) any = any || (node.in_window && !node.closed);
    if (!any) break;
    if (!read(milliseconds(200))) continue;
    for (Node& node : nodes_) node.reports.clear();
  }
  // A run that reached its end still fails for a node that lied on the way
  // (a report past the window, an end its reports did not reach).
  if (step_ + 1 == total_)
    for (const Node& node : nodes_)
      if (node.failed && !node.step_failure) throw NodeFailure(node.fail_text);
}

}  // namespace railcosim::remote
