#include "cli/conform_peer.hpp"

#include <map>
#include <vector>

#include "auth.hpp"
#include "model.hpp"

namespace railcosim::cli {
namespace {

// The reply to a peer's hello at the subject's port (after the challenge,
// answered rightly, when it has a secret).
wire::Envelope peer_hello(const ConformOptions& o, const std::string& participant,
                          const std::string& peer_of, const std::string& session) {
  auto c = Connection::connect(o.address, std::chrono::milliseconds(5000));
  wire::Envelope hello;
  auto* h = hello.mutable_hello();
  h->set_protocol_version(kProtocolVersion);
  h->set_role("peer");
  h->set_participant(participant);
  h->set_peer_of(peer_of);
  h->set_session(session);
  h->set_name("conformance kit");
  c->send(hello);
  wire::Envelope reply = c->receive(o.reply);
  if (reply.has_challenge() && o.token) {
    wire::Envelope auth;
    auth.mutable_auth()->set_mac(auth_answer(*o.token, participant, reply.challenge().nonce()));
    c->send(auth);
    reply = c->receive(o.reply);
  }
  return reply;
}

std::string refused_with(const wire::Envelope& reply, wire::Error::Code code,
                         const std::string& what) {
  if (reply.has_error() && reply.error().code() == code) return "";
  if (reply.has_error())
    return what + " was answered " + wire::Error::Code_Name(reply.error().code()) + ": " +
           reply.error().message() + " (expected " + wire::Error::Code_Name(code) + ")";
  return what + " was accepted (" + body_name(reply) + ")";
}

}  // namespace

std::string check_peer_refusals(Connection& master, const SubsystemConfig& config,
                                const ConformOptions& o) {
  // Every peer the subject has connects to it (an empty host): its port
  // then waits for them once the first window is granted.
  const std::string session(16, '\x5a');
  wire::Envelope e;
  auto* links = e.mutable_links();
  links->set_session(session);
  links->set_timeout_ms(static_cast<std::uint32_t>(3 * o.reply.count()));
  std::map<std::string, wire::PeerLink*> by_peer;
  const auto& ifs = config.participant.interfaces;
  for (std::size_t j = 0; j < ifs.size(); ++j) {
    wire::PeerLink*& l = by_peer[ifs[j].peer_role];
    if (!l) {
      l = links->add_links();
      l->set_peer(ifs[j].peer_role);
    }
    l->add_interfaces(static_cast<int>(j));
  }
  if (by_peer.empty()) return "skipped: the participant has no peers in this case";
  master.send(e);
  const wire::Envelope ack = master.receive(o.reply);
  if (!ack.has_ack())
    return "skipped: the participant does not take peer links (" + body_name(ack) + ")";
  wire::Envelope w;
  w.mutable_window()->set_first_step(0);
  w.mutable_window()->set_end_step(1);
  master.send(w);

  const std::string& me = config.participant.role;
  const std::string expected = by_peer.begin()->first;
  if (std::string why = refused_with(
          peer_hello(o, me, expected, std::string(16, '\x33')), wire::Error::UNAUTHORIZED,
          "a link from the " + expected + " participant with the wrong session key");
      !why.empty())
    return why;
  std::string stranger = "track";
  for (const std::string& r : role_names())
    if (r != me && !by_peer.count(r)) stranger = r;
  return refused_with(
      peer_hello(o, me, stranger, session), wire::Error::WRONG_ROLE,
      "a link with the right key from the " + stranger + " participant, which it does not expect,");
}

}  // namespace railcosim::cli
