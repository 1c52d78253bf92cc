#include "peer_handshake.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "auth.hpp"

namespace railcosim {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

struct PeerHandshakes::Pending {
  int fd = -1;
  std::string from;
  FrameDecoder decoder{kPeerHandshakeFrameBytes};
  Clock::time_point deadline;
  std::optional<wire::Hello> hello;
  std::uint64_t hello_id = 0;
  std::string nonce;  // of the challenge sent, if any
};

namespace {

// Refusals kept word for word in the error of a link that never opens.
constexpr std::size_t kRefusalsNamed = 5;

// Best effort: a short frame to a fresh connection, which has room for it.
void send_quietly(int fd, const wire::Envelope& e) {
  try {
    write_all(fd, encode_frame(e), milliseconds(200), "a peer connection");
  } catch (const LinkError&) {
  }
}

}  // namespace

PeerHandshakes::PeerHandshakes(const LinksPlan& plan, const LinkIdentity& me,
                               const std::vector<bool>& open)
    : plan_(plan), me_(me), open_(open) {}

PeerHandshakes::~PeerHandshakes() {
  for (const auto& p : pending_) {
    send_quietly(p->fd, error_envelope(0, wire::Error::BUSY, kBusyText));
    ::close(p->fd);
  }
}

void PeerHandshakes::add(int fd, std::string from) {
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
  auto p = std::make_unique<Pending>();
  p->fd = fd;
  p->from = std::move(from);
  p->deadline = Clock::now() + kPeerHandshakeTimeout;
  // A peer's hello is usually there already: it is answered at once.
  if (advance(*p)) return;
  if (pending_.size() >= kMaxPeerHandshakes) {
    auto victim = pending_.begin();
    for (auto it = pending_.begin(); it != pending_.end(); ++it)
      if (!(*it)->hello && (*it)->decoder.buffered() == 0) {
        victim = it;
        break;
      }
    refuse(**victim, wire::Error::BUSY, kBusyText, "closed for a newer connection");
    pending_.erase(victim);
  }
  pending_.push_back(std::move(p));
}

std::optional<PeerHandshakes::Accepted> PeerHandshakes::serve(milliseconds wait) {
  if (done_.empty() && !pending_.empty()) {
    std::vector<pollfd> fds;
    for (const auto& p : pending_) fds.push_back(pollfd{p->fd, POLLIN, 0});
    auto soonest = pending_.front()->deadline;
    for (const auto& p : pending_) soonest = std::min(soonest, p->deadline);
    const auto until = std::chrono::duration_cast<milliseconds>(soonest - Clock::now());
    const int ms = static_cast<int>(std::clamp(until, milliseconds(0), wait).count());
    const int ready = ::poll(fds.data(), fds.size(), ms);
    std::deque<std::unique_ptr<Pending>> still;
    for (std::size_t k = 0; k < pending_.size(); ++k) {
      Pending& p = *pending_[k];
      if (ready > 0 && fds[k].revents != 0 && advance(p)) continue;
      if (Clock::now() >= p.deadline) {
        refuse(p, wire::Error::TIMEOUT,
               "the peer handshake was not done within " +
                   std::to_string(kPeerHandshakeTimeout.count()) + " ms of connecting");
        continue;
      }
      still.push_back(std::move(pending_[k]));
    }
    pending_ = std::move(still);
  }
  if (done_.empty()) return std::nullopt;
  Accepted a = std::move(done_.front());
  done_.pop_front();
  return a;
}

bool PeerHandshakes::advance(Pending& p) {
  char buf[4096];
  while (true) {
    const ssize_t n = ::recv(p.fd, buf, sizeof buf, 0);
    if (n > 0) {
      p.decoder.feed(buf, static_cast<std::size_t>(n));
      if (p.decoder.buffered() > 2 * kPeerHandshakeFrameBytes) break;  // enough to decide
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    note(p.from, "closed the connection during the peer handshake");
    ::close(p.fd);
    return true;
  }
  wire::Envelope e;
  switch (p.decoder.next(e)) {
    case FrameDecoder::Status::kNeedMore:
      return false;
    case FrameDecoder::Status::kTooLarge:
      refuse(p, wire::Error::FRAME_TOO_LARGE,
             "a frame of " + std::to_string(p.decoder.announced()) +
                 " bytes in a peer handshake, whose frames are at most " +
                 std::to_string(kPeerHandshakeFrameBytes) + " bytes");
      return true;
    case FrameDecoder::Status::kBadFrame:
      refuse(p, wire::Error::BAD_FRAME, "a frame did not decode as a message");
      return true;
    case FrameDecoder::Status::kFrame:
      break;
  }
  if (!p.hello) {
    if (!e.has_hello() || e.hello().role() != "peer") {
      refuse(p, wire::Error::BUSY, kBusyText, "not a peer link (" + body_name(e) + ")");
      return true;
    }
    if (e.hello().protocol_version() != kProtocolVersion) {
      refuse(p, wire::Error::VERSION_MISMATCH,
             "protocol version " + std::to_string(e.hello().protocol_version()) +
                 " is not supported; this node speaks version " + std::to_string(kProtocolVersion));
      return true;
    }
    p.hello = e.hello();
    p.hello_id = e.id();
    if (!me_.token) return admit(p);
    p.nonce = random_nonce();
    wire::Envelope challenge;
    challenge.mutable_challenge()->set_nonce(p.nonce);
    send_quietly(p.fd, challenge);
    return false;
  }
  if (!e.has_auth() ||
      !constant_time_equal(e.auth().mac(), auth_answer(*me_.token, me_.participant, p.nonce))) {
    refuse(p, wire::Error::UNAUTHORIZED,
           "this node requires the shared secret of its --token-file; the answer to its "
           "challenge was missing or wrong");
    return true;
  }
  return admit(p);
}

bool PeerHandshakes::admit(Pending& p) {
  const wire::Hello& h = *p.hello;
  // The session key first: until it is right, no participant is named.
  if (!constant_time_equal(h.session(), plan_.session)) {
    refuse(p, wire::Error::UNAUTHORIZED, "the session key presented is not this session's",
           "a wrong session key (as " + participant_text(h.peer_of()) + ")");
    return true;
  }
  if (h.participant() != me_.participant) {
    refuse(p, wire::Error::WRONG_ROLE,
           "this node serves " + participant_text(me_.participant) + ", not " +
               participant_text(h.participant()));
    return true;
  }
  std::size_t index = plan_.links.size();
  std::string expected;
  for (std::size_t k = 0; k < plan_.links.size(); ++k) {
    const LinkPlan& l = plan_.links[k];
    if (l.connect || open_[k]) continue;
    bool taken = false;
    for (const Accepted& a : done_) taken = taken || a.index == k;
    if (taken) continue;
    expected += (expected.empty() ? "" : ", ") + l.peer;
    if (l.peer == h.peer_of()) index = k;
  }
  if (index == plan_.links.size()) {
    refuse(p, wire::Error::WRONG_ROLE,
           "this node expects peer links from " + (expected.empty() ? "nobody" : expected) +
               ", not from " + participant_text(h.peer_of()));
    return true;
  }
  wire::Envelope reply;
  reply.set_id(p.hello_id);
  auto* r = reply.mutable_hello_reply();
  r->set_protocol_version(kProtocolVersion);
  r->set_participant(me_.participant);
  r->set_name(me_.name);
  // This end proves the secret too, to a connecting end that asked.
  if (me_.token && !h.nonce().empty())
    r->set_proof(auth_proof(*me_.token, me_.participant, h.nonce(), p.nonce));
  auto ch = std::make_unique<FdChannel>(p.fd, participant_text(h.peer_of()) + " at " + p.from,
                                        me_.max_frame_bytes);
  p.fd = -1;  // the channel owns it now
  try {
    ch->send(reply, milliseconds(1000));
  } catch (const LinkError& e) {
    note(p.from, e.what());
    return true;
  }
  done_.push_back({index, std::move(ch)});
  return true;
}

void PeerHandshakes::refuse(Pending& p, wire::Error::Code code, const std::string& why,
                            const std::string& note_text) {
  send_quietly(p.fd, error_envelope(p.hello_id, code, why));
  ::close(p.fd);
  p.fd = -1;
  note(p.from, note_text.empty() ? why : note_text);
}

void PeerHandshakes::note(const std::string& from, const std::string& why) {
  if (refused_count_++ < kRefusalsNamed) refused_.push_back(from + ": " + why);
}

std::string PeerHandshakes::refused() const {
  std::string s;
  for (const std::string& r : refused_) s += (s.empty() ? "" : "; ") + r;
  if (refused_count_ > refused_.size())
    s += "; and " + std::to_string(refused_count_ - refused_.size()) + " more";
  return s;
}

}  // namespace railcosim
