#include "peer_links.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <set>
#include <thread>

#include "auth.hpp"
#include "peer_handshake.hpp"

namespace railcosim {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

LinksPlan links_from_wire(const wire::Links& w, std::size_t interface_count,
                          const std::string& participant) {
  auto bad = [&](const std::string& why) {
    std::string m = "links for the ";
    m += participant;
    m += " participant: ";
    m += why;
    return ProtocolError(wire::Error::BAD_REQUEST, m);
  };
  LinksPlan plan;
  plan.session = w.session();
  plan.refresh = w.refresh();
  plan.timeout = milliseconds(w.timeout_ms() > 0 ? w.timeout_ms() : 10000);
  if (plan.session.size() < 16) throw bad("the session key must have at least 16 bytes");
  std::vector<int> covered(interface_count, 0);
  std::set<std::string> peers;
  for (const auto& l : w.links()) {
    LinkPlan p;
    p.peer = l.peer();
    if (p.peer.empty() || p.peer == participant) throw bad("a link names no other participant");
    if (!peers.insert(p.peer).second) throw bad("two links to the " + p.peer + " participant");
    if (!l.host().empty()) {
      if (l.port() == 0 || l.port() > 65535) throw bad("the link to " + p.peer + " has no port");
      p.connect = Address{l.host(), static_cast<std::uint16_t>(l.port())};
    }
    for (int i : l.interfaces()) {
      if (i < 0 || static_cast<std::size_t>(i) >= interface_count)
        throw bad("interface " + std::to_string(i) + " does not exist");
      ++covered[static_cast<std::size_t>(i)];
      p.interfaces.push_back(i);
    }
    if (p.interfaces.empty()) throw bad("the link to " + p.peer + " carries no interface");
    p.ahead = l.ahead();
    p.refreshes = l.refreshes();
    plan.links.push_back(std::move(p));
  }
  for (std::size_t i = 0; i < interface_count; ++i)
    if (covered[i] != 1)
      throw bad("interface " + std::to_string(i) + " faces " + std::to_string(covered[i]) +
                " links instead of one");
  return plan;
}

PeerInbox::~PeerInbox() {
  // Connections never taken up (a master that came while the session ended)
  // hear BUSY, which a master asks again after, rather than a bare close.
  const std::string busy = encode_frame(error_envelope(0, wire::Error::BUSY, kBusyText));
  for (const Offered& o : queue_) {
    [[maybe_unused]] const auto sent =
        ::send(o.fd, busy.data(), busy.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    ::close(o.fd);
  }
}

void PeerInbox::set_waiting(bool waiting) {
  std::lock_guard<std::mutex> lock(mutex_);
  waiting_ = waiting;
}

bool PeerInbox::waiting() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return waiting_;
}

void PeerInbox::offer(int fd, std::string from) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // A flood waiting to be taken up holds no more than this many sockets.
    if (queue_.size() >= kMaxPeerHandshakes) {
      ::close(queue_.front().fd);
      queue_.pop_front();
    }
    queue_.push_back({fd, std::move(from)});
  }
  cv_.notify_one();
}

void PeerInbox::track(int fd) {
  std::lock_guard<std::mutex> lock(mutex_);
  live_.push_back(fd);
}

void PeerInbox::shut_down_links() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int fd : live_) ::shutdown(fd, SHUT_RDWR);
}

void PeerInbox::cancel() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cancelled_ = true;
  }
  cv_.notify_all();
}

PeerInbox::Offered PeerInbox::take(Clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!cv_.wait_until(lock, deadline, [this] { return cancelled_ || !queue_.empty(); }) ||
      queue_.empty()) {
    Offered none;
    none.cancelled = cancelled_;
    return none;
  }
  Offered o = std::move(queue_.front());
  queue_.pop_front();
  return o;
}

namespace {

milliseconds left(Clock::time_point deadline) {
  return std::max(milliseconds(1),
                  std::chrono::duration_cast<milliseconds>(deadline - Clock::now()));
}

// The connecting end: hello, the challenge if the peer's node asks, its reply.
std::unique_ptr<FdChannel> connect_link(const LinksPlan& plan, const LinkPlan& l,
                                        const LinkIdentity& me, Clock::time_point deadline) {
  const std::string who = participant_text(l.peer) + " at " + l.connect->str();
  std::unique_ptr<Connection> c;
  try {
    c = Connection::connect(*l.connect, left(deadline));
  } catch (const NetError& e) {
    throw ProtocolError(wire::Error::TIMEOUT, "peer link to " + who + ": " + e.what());
  }
  auto ch = std::make_unique<FdChannel>(c->release_fd(), who, me.max_frame_bytes);
  wire::Envelope hello;
  auto* h = hello.mutable_hello();
  h->set_protocol_version(kProtocolVersion);
  h->set_role("peer");
  h->set_participant(l.peer);
  h->set_peer_of(me.participant);
  h->set_session(plan.session);
  h->set_name(me.name);
  const std::string mine = me.token ? random_nonce() : std::string();
  h->set_nonce(mine);
  ch->send(hello, left(deadline));
  wire::Envelope reply = ch->receive(left(deadline));
  const std::string challenge = reply.has_challenge() ? reply.challenge().nonce() : "";
  if (reply.has_challenge()) {
    if (!me.token)
      throw ProtocolError(wire::Error::UNAUTHORIZED,
                          "peer link to " + who +
                              ": that node requires a shared secret; start this node with the "
                              "same --token-file");
    wire::Envelope auth;
    auth.mutable_auth()->set_mac(auth_answer(*me.token, l.peer, reply.challenge().nonce()));
    ch->send(auth, left(deadline));
    reply = ch->receive(left(deadline));
  }
  if (reply.has_error())
    throw ProtocolError(reply.error().code(), "peer link to " + who + " refused: " +
                                                  wire::Error::Code_Name(reply.error().code()) +
                                                  ": " + reply.error().message());
  if (!reply.has_hello_reply() || reply.hello_reply().participant() != l.peer)
    throw ProtocolError(wire::Error::WRONG_ROLE,
                        "peer link to " + who + ": the node there does not serve " + l.peer);
  // With a secret, the accepting end must prove it holds it too.
  if (me.token) {
    const std::string why =
        proof_failure(*me.token, l.peer, mine, challenge, reply.hello_reply().proof());
    if (!why.empty())
      throw ProtocolError(wire::Error::UNAUTHORIZED, "peer link to " + who + ": " + why);
  }
  return ch;
}

// connect_link again while the accepting node turns the connection away
// without a verdict (closed, reset, BUSY, no answer within twice its
// handshake bound: a flood may have crowded it out), until the deadline.
// The master hears, before the first retry, whom this node waits for.
std::unique_ptr<FdChannel> connect_link_retrying(
    const LinksPlan& plan, const LinkPlan& l, const LinkIdentity& me, Clock::time_point deadline,
    const std::function<bool()>& abandoned,
    const std::function<void(const std::string&)>& waiting) {
  for (int tries = 0;; ++tries) {
    if (tries == 1 && waiting) waiting(l.peer);
    if (tries > 0 && abandoned && abandoned())
      throw ProtocolError(wire::Error::PEER_FAILED,
                          "the master ended the session while the peer links were opening");
    const auto attempt = std::min(deadline, Clock::now() + 2 * kPeerHandshakeTimeout);
    try {
      return connect_link(plan, l, me, attempt);
    } catch (const LinkError&) {
      if (Clock::now() + milliseconds(100) >= deadline) throw;
    } catch (const ProtocolError& e) {
      if (e.code() != wire::Error::BUSY || Clock::now() + milliseconds(100) >= deadline) throw;
    }
    std::this_thread::sleep_for(milliseconds(100));
  }
}

}  // namespace

std::vector<std::unique_ptr<FdChannel>> open_links(
    const LinksPlan& plan, const LinkIdentity& me, PeerInbox& inbox,
    const std::function<bool()>& abandoned,
    const std::function<void(const std::string&)>& waiting) {
  const auto start = Clock::now();
  const auto deadline = start + plan.timeout;
  std::vector<std::unique_ptr<FdChannel>> out(plan.links.size());
  std::vector<bool> open(plan.links.size(), false);
  std::size_t to_accept = 0;
  for (const LinkPlan& l : plan.links)
    if (!l.connect) ++to_accept;
  inbox.set_waiting(to_accept > 0);
  auto missing = [&] {
    std::string m;
    for (std::size_t k = 0; k < plan.links.size(); ++k)
      if (!open[k]) m += (m.empty() ? "" : ", ") + plan.links[k].peer;
    return m;
  };
  try {
    for (std::size_t k = 0; k < plan.links.size(); ++k)
      if (plan.links[k].connect) {
        out[k] = connect_link_retrying(plan, plan.links[k], me, deadline, abandoned, waiting);
        open[k] = true;
      }
    PeerHandshakes handshakes(plan, me, open);
    bool told = false;
    auto next_probe = start;
    while (to_accept > 0) {
      const auto now = Clock::now();
      // Connections the server accepted meanwhile; a wait here only when
      // no handshake is under way.
      PeerInbox::Offered o =
          inbox.take(handshakes.idle() ? std::min(deadline, now + milliseconds(100)) : now);
      while (!o.cancelled && o.fd >= 0) {
        handshakes.add(o.fd, std::move(o.from));
        o = inbox.take(Clock::now());
      }
      if (o.cancelled) throw ProtocolError(wire::Error::PEER_FAILED, "the node stops");
      if (!handshakes.idle())
        if (auto a = handshakes.serve(milliseconds(5))) {
          out[a->index] = std::move(a->channel);
          open[a->index] = true;
          --to_accept;
          continue;
        }
      // The master learns whom this node waits for, so that it names that
      // node if the link never opens.
      if (!told && waiting && Clock::now() - start >= milliseconds(50)) {
        for (std::size_t k = 0; k < plan.links.size() && !told; ++k)
          if (!open[k]) {
            waiting(plan.links[k].peer);
            told = true;
          }
      }
      if (Clock::now() >= next_probe) {
        next_probe = Clock::now() + milliseconds(100);
        if (abandoned && abandoned())
          throw ProtocolError(wire::Error::PEER_FAILED,
                              "the master ended the session while the peer links were opening");
      }
      if (Clock::now() >= deadline) {
        const std::string refused = handshakes.refused();
        throw ProtocolError(wire::Error::TIMEOUT,
                            "the peer link(s) from " + missing() + " did not open within " +
                                std::to_string(plan.timeout.count()) + " ms" +
                                (refused.empty() ? "" : " (refused meanwhile: " + refused + ")"));
      }
    }
  } catch (...) {
    inbox.set_waiting(false);
    throw;
  }
  inbox.set_waiting(false);
  for (const auto& l : out) inbox.track(l->fd());
  return out;
}

}  // namespace railcosim
