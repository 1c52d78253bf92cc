// Framed messages over a plain blocking socket: the direct data plane's
// links between nodes. One `send` and, when a frame arrives whole, one `recv`
// per message: no event loop, no timer re-armed per read (the receive
// deadline is a socket option, set again only when it changes).
#pragma once

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "wire.hpp"

namespace railcosim {

// A link that failed: closed by the peer, silent past its deadline, or
// carrying something that is not a frame.
class LinkError : public std::runtime_error {
 public:
  enum class Kind { kClosed, kTimeout, kIo, kProtocol };
  LinkError(Kind kind, const std::string& what, std::string sender = "")
      : std::runtime_error(what), kind_(kind), sender_(std::move(sender)) {}
  Kind kind() const { return kind_; }
  // The participant whose data or frames were refused ("" if none is to blame).
  const std::string& sender() const { return sender_; }

 private:
  Kind kind_;
  std::string sender_;
};

class FdChannel {
 public:
  // Takes ownership of a connected TCP socket: makes it blocking and sets
  // TCP_NODELAY. `what` names the other end in errors ("the soil participant").
  // Frames over `max_frame_bytes` are neither read nor sent.
  FdChannel(int fd, std::string what, std::size_t max_frame_bytes = kDefaultMaxFrameBytes);
  ~FdChannel();
  FdChannel(const FdChannel&) = delete;
  FdChannel& operator=(const FdChannel&) = delete;

  // Writes one frame whole, within `timeout`. Throws LinkError.
  void send(const wire::Envelope& envelope, std::chrono::milliseconds timeout);
  void send_frame(const std::string& frame, std::chrono::milliseconds timeout);
  // Reads one frame; the peer must send it within `timeout`. Throws LinkError.
  wire::Envelope receive(std::chrono::milliseconds timeout);
  const std::string& what() const { return what_; }
  void rename(std::string what) { what_ = std::move(what); }
  int fd() const { return fd_; }

 private:
  void set_timeout(int option, std::chrono::milliseconds timeout, std::chrono::milliseconds& now);

  int fd_;
  std::string what_;
  std::size_t max_frame_bytes_;
  FrameDecoder decoder_;
  std::vector<char> buffer_;
  std::chrono::milliseconds recv_timeout_{-1}, send_timeout_{-1};
};

// Writes all of `bytes` to a socket that may be non-blocking (waits with poll
// when it is full), within `timeout`. Throws LinkError naming `what`.
void write_all(int fd, const std::string& bytes, std::chrono::milliseconds timeout,
               const std::string& what);

}  // namespace railcosim
