// The peer links of one session on the direct data plane: what the master
// asked for (Links), the sockets other nodes open to this one, and the
// handshake on both ends (hello as role "peer", the session key, the shared
// secret's challenge when the accepting node has one).
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "connection.hpp"
#include "fd_channel.hpp"
#include "wire.hpp"

namespace railcosim {

// What a node answers (BUSY) to any connection it cannot serve while a
// session runs: the same words whether or not peer links are opening.
inline constexpr const char* kBusyText =
    "this node already serves a session; try again when it has ended";

struct LinkPlan {
  std::string peer;                // the participant at the other end
  std::optional<Address> connect;  // set: connect there; unset: the peer connects here
  std::vector<int> interfaces;     // this participant's interfaces facing the peer
  bool ahead = false;              // Gauss–Seidel: the peer steps first
  bool refreshes = false;          // resolved feedthrough: the peer sends twice per step
};

struct LinksPlan {
  std::string session;  // the key peers present
  std::vector<LinkPlan> links;
  bool refresh = false;
  std::chrono::milliseconds timeout{10000};
};

// Checks a Links request against a participant with `interface_count`
// interfaces: every interface faces exactly one link. Throws
// ProtocolError(BAD_REQUEST) saying what does not fit.
LinksPlan links_from_wire(const wire::Links& w, std::size_t interface_count,
                          const std::string& participant);

// Sockets that connected to this node while its session waits for peers.
// The server's accepting thread offers them; the session's worker takes them.
class PeerInbox {
 public:
  ~PeerInbox();
  void set_waiting(bool waiting);
  bool waiting() const;
  void offer(int fd, std::string from);
  struct Offered {
    int fd = -1;
    std::string from;
    bool cancelled = false;
  };
  // The next socket, or fd -1 once `deadline` has passed.
  Offered take(std::chrono::steady_clock::time_point deadline);
  // The open links, so that a node told to stop can break them (a window
  // blocked on a peer then ends at once): any thread.
  void track(int fd);
  void shut_down_links();
  // The node stops: take() returns at once from now on.
  void cancel();

 private:
  mutable std::mutex mutex_;
  std::vector<int> live_;
  bool cancelled_ = false;
  std::condition_variable cv_;
  bool waiting_ = false;
  std::deque<Offered> queue_;
};

struct LinkIdentity {
  std::string participant;                              // the participant this node serves
  std::optional<std::string> token;                     // this node's shared secret, if any
  std::string name;                                     // for logs
  std::size_t max_frame_bytes = kDefaultMaxFrameBytes;  // on the links, both ways
};

// Opens every link of `plan` (connecting where it says so, accepting the
// others from `inbox`), returns them in the plan's order, each named after its
// peer and the peer's address. Incoming connections are served side by side,
// each within kPeerHandshakeTimeout (peer_handshake.hpp); one that is not an
// expected peer is refused and the wait goes on. Throws ProtocolError naming
// the peer when a link cannot be made within the plan's timeout.
// `abandoned` is asked every 100 ms while the links open: true when the
// master has gone (the wait then ends with PEER_FAILED). `waiting` is told,
// once, the peer this node still waits for after 50 ms.
std::vector<std::unique_ptr<FdChannel>> open_links(
    const LinksPlan& plan, const LinkIdentity& me, PeerInbox& inbox,
    const std::function<bool()>& abandoned,
    const std::function<void(const std::string&)>& waiting = {});

}  // namespace railcosim
