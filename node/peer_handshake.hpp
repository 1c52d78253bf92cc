// The accepting end of a session's peer links. Every connection that arrives
// while the links open gets its own short deadline for its hello and its
// answer to the challenge, and all of them are served side by side: a
// connection that stays silent, or a flood of them, holds up nobody else.
//
// Before a connection has proved it may open a link (the shared secret's
// challenge when the node has one, else the session key), it learns nothing
// but that this node is busy: not whom the node serves, not which peers it
// expects.
#pragma once

#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fd_channel.hpp"
#include "peer_links.hpp"

namespace railcosim {

// The whole handshake (hello, challenge, answer) of one incoming peer
// connection must be done within this time of the node taking it up.
inline constexpr std::chrono::milliseconds kPeerHandshakeTimeout{2000};
// Handshake frames are small: a larger one is refused before it is read.
inline constexpr std::size_t kPeerHandshakeFrameBytes = 4096;
// At most this many handshakes at once (and sockets waiting to be taken up);
// a further connection closes the oldest that has not said anything yet, or
// else the oldest (a connecting node tries again until its link deadline).
inline constexpr std::size_t kMaxPeerHandshakes = 256;

// "the vehicle participant": how peer-link errors name a participant.
inline std::string participant_text(const std::string& p) {
  return "the " + p + " participant";
}

class PeerHandshakes {
 public:
  // `open[k]`: link k of `plan` is open (or is one this node connects).
  PeerHandshakes(const LinksPlan& plan, const LinkIdentity& me, const std::vector<bool>& open);
  ~PeerHandshakes();  // closes the connections still pending
  PeerHandshakes(const PeerHandshakes&) = delete;
  PeerHandshakes& operator=(const PeerHandshakes&) = delete;

  // Takes up a connection the server accepted.
  void add(int fd, std::string from);
  bool idle() const { return pending_.empty() && done_.empty(); }

  struct Accepted {
    std::size_t index;  // in the plan
    std::unique_ptr<FdChannel> channel;
  };
  // Serves the pending connections for up to `wait`; returns one whose
  // handshake succeeded, if any. Refused and overdue ones are closed.
  std::optional<Accepted> serve(std::chrono::milliseconds wait);

  // The refusals so far, for the error of a link that never opened.
  std::string refused() const;

 private:
  struct Pending;
  // Reads what `p` sent and answers it; true when `p` is done with (accepted or refused).
  bool advance(Pending& p);
  // True when `p` is an expected peer (and sends it the HelloReply); else refuses it.
  bool admit(Pending& p);
  void refuse(Pending& p, wire::Error::Code code, const std::string& why,
              const std::string& note = "");
  void note(const std::string& from, const std::string& why);

  const LinksPlan& plan_;
  const LinkIdentity& me_;
  const std::vector<bool>& open_;
  std::deque<std::unique_ptr<Pending>> pending_;
  std::deque<Accepted> done_;
  std::vector<std::string> refused_;
  std::size_t refused_count_ = 0;
};

}  // namespace railcosim
