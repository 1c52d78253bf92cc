// What the master needs of a connection to a node: whole frames sent and
// received within deadlines, a name of the peer for messages, and a way to
// end it. `Connection` (connection.hpp) is the TCP one; tests add an
// in-process one (two queues of frames between two threads). What only a
// socket can do (poll several at once, hand the descriptor over) stays on
// `Connection`, which tcp() returns.
#pragma once

#include <chrono>
#include <stdexcept>
#include <string>

#include "wire.hpp"

namespace railcosim {

// A network failure: the peer closed the connection, did not answer in time,
// or sent something that is not a frame.
class NetError : public std::runtime_error {
 public:
  enum class Kind { kConnect, kClosed, kTimeout, kIo, kProtocol, kInterrupted };
  NetError(Kind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

class Connection;

class FramedChannel {
 public:
  using Duration = std::chrono::milliseconds;

  virtual ~FramedChannel() = default;

  // Every timeout bounds a whole message: a peer that sends a reply one byte
  // at a time does not restart it.
  // Writes one frame. Throws NetError on failure or after `timeout`
  // (kClosed once the peer has gone, kTimeout past the deadline).
  virtual void send(const wire::Envelope& envelope, Duration timeout) = 0;
  // Reads one frame. Throws NetError if none arrives within `timeout`
  // (kTimeout), the peer has closed the channel (kClosed) or its bytes are
  // not a frame (kProtocol).
  virtual wire::Envelope receive(Duration timeout) = 0;
  // The peer, for messages ("127.0.0.1:4001").
  virtual std::string peer_name() const = 0;
  // Ends the channel in both directions; the peer reads end of stream.
  virtual void close() = 0;
  // The TCP connection under this channel, or nullptr: the direct data plane
  // polls sockets and works only over TCP.
  virtual Connection* tcp() { return nullptr; }
};

}  // namespace railcosim
