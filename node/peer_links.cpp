#include "peer_links.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <set>

#include "auth.hpp"

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
  for (const Offered& o : queue_) ::close(o.fd);
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

std::string participant_text(const std::string& p) {
  std::string s = "the ";
  s += p;
  s += " participant";
  return s;
}

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
  auto ch = std::make_unique<FdChannel>(c->release_fd(), who);
  wire::Envelope hello;
  auto* h = hello.mutable_hello();
  h->set_protocol_version(kProtocolVersion);
  h->set_role("peer");
  h->set_participant(l.peer);
  h->set_peer_of(me.participant);
  h->set_session(plan.session);
  h->set_name(me.name);
  ch->send(hello, left(deadline));
  wire::Envelope reply = ch->receive(left(deadline));
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
  return ch;
}

// The accepting end: which expected peer this connection is, or why it is refused.
int accept_link(const LinksPlan& plan, const LinkIdentity& me, FdChannel& ch,
                const std::vector<bool>& open, Clock::time_point deadline) {
  const wire::Envelope e = ch.receive(left(deadline));
  auto refuse = [&](wire::Error::Code code, const std::string& why) -> int {
    try {
      ch.send(error_envelope(e.id(), code, why), milliseconds(1000));
    } catch (const LinkError&) {
    }
    throw ProtocolError(code, why);
  };
  if (!e.has_hello() || e.hello().role() != "peer")
    refuse(wire::Error::BUSY, "this node serves a session; it accepts nothing but its peer links");
  const wire::Hello& h = e.hello();
  if (h.participant() != me.participant)
    refuse(wire::Error::WRONG_ROLE, "this node serves " + participant_text(me.participant) +
                                        ", not " + participant_text(h.participant()));
  int index = -1;
  std::string expected;
  for (std::size_t k = 0; k < plan.links.size(); ++k) {
    const LinkPlan& l = plan.links[k];
    if (l.connect || open[k]) continue;
    expected += (expected.empty() ? "" : ", ") + l.peer;
    if (l.peer == h.peer_of()) index = static_cast<int>(k);
  }
  if (index < 0)
    refuse(wire::Error::WRONG_ROLE, "this node expects peer links from " +
                                        (expected.empty() ? "nobody" : expected) + ", not from " +
                                        participant_text(h.peer_of()));
  if (!constant_time_equal(h.session(), plan.session))
    refuse(wire::Error::UNAUTHORIZED,
           "the session key of " + participant_text(h.peer_of()) + " is not this session's");
  if (me.token) {
    const std::string nonce = random_nonce();
    wire::Envelope challenge;
    challenge.mutable_challenge()->set_nonce(nonce);
    ch.send(challenge, left(deadline));
    const wire::Envelope answer = ch.receive(left(deadline));
    if (!answer.has_auth() ||
        !constant_time_equal(answer.auth().mac(), auth_answer(*me.token, me.participant, nonce)))
      refuse(wire::Error::UNAUTHORIZED,
             "this node requires the shared secret of its --token-file; the answer of " +
                 participant_text(h.peer_of()) + " to its challenge was missing or wrong");
  }
  wire::Envelope reply;
  reply.set_id(e.id());
  auto* r = reply.mutable_hello_reply();
  r->set_protocol_version(kProtocolVersion);
  r->set_participant(me.participant);
  r->set_name(me.name);
  ch.send(reply, left(deadline));
  return index;
}

}  // namespace

std::vector<std::unique_ptr<FdChannel>> open_links(const LinksPlan& plan, const LinkIdentity& me,
                                                   PeerInbox& inbox,
                                                   const std::function<bool()>& abandoned) {
  const auto deadline = Clock::now() + plan.timeout;
  std::vector<std::unique_ptr<FdChannel>> out(plan.links.size());
  std::vector<bool> open(plan.links.size(), false);
  std::size_t to_accept = 0;
  for (const LinkPlan& l : plan.links)
    if (!l.connect) ++to_accept;
  inbox.set_waiting(to_accept > 0);
  std::string refused;
  try {
    for (std::size_t k = 0; k < plan.links.size(); ++k)
      if (plan.links[k].connect) {
        out[k] = connect_link(plan, plan.links[k], me, deadline);
        open[k] = true;
      }
    while (to_accept > 0) {
      PeerInbox::Offered o = inbox.take(std::min(deadline, Clock::now() + milliseconds(100)));
      if (o.cancelled) throw ProtocolError(wire::Error::PEER_FAILED, "the node stops");
      if (o.fd < 0 && abandoned && abandoned())
        throw ProtocolError(wire::Error::PEER_FAILED,
                            "the master ended the session while the peer links were opening");
      if (o.fd < 0 && Clock::now() < deadline) continue;
      if (o.fd < 0) {
        std::string missing;
        for (std::size_t k = 0; k < plan.links.size(); ++k)
          if (!open[k]) missing += (missing.empty() ? "" : ", ") + plan.links[k].peer;
        throw ProtocolError(wire::Error::TIMEOUT,
                            "the peer link(s) from " + missing + " did not open within " +
                                std::to_string(plan.timeout.count()) + " ms" +
                                (refused.empty() ? "" : " (refused meanwhile: " + refused + ")"));
      }
      auto ch = std::make_unique<FdChannel>(o.fd, "a connection from " + o.from);
      try {
        const int k = accept_link(plan, me, *ch, open, deadline);
        out[static_cast<std::size_t>(k)] = std::move(ch);
        open[static_cast<std::size_t>(k)] = true;
        --to_accept;
      } catch (const std::exception& e) {
        refused += (refused.empty() ? "" : "; ") + o.from + ": " + e.what();
      }
    }
  } catch (...) {
    inbox.set_waiting(false);
    throw;
  }
  inbox.set_waiting(false);
  // Each link is named after its peer in the errors of the window.
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k]->rename(participant_text(plan.links[k].peer));
    inbox.track(out[k]->fd());
  }
  return out;
}

}  // namespace railcosim
