#include "frame_source.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace railcosim {

void FrameSource::set_blocking(bool on) {
  const int flags = ::fcntl(fd_, F_GETFL, 0);
  if (flags < 0) return;
  if (::fcntl(fd_, F_SETFL, on ? flags & ~O_NONBLOCK : flags | O_NONBLOCK) < 0) return;
  // Sends time out too, so that a writer's deadline (write_all) still holds.
  timeval tv{0, on ? 100000 : 0};
  ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ::setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  blocking_ = on;
}

bool FrameSource::hung_up() const {
  pollfd p{fd_, POLLRDHUP, 0};
  return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

bool FrameSource::next(wire::Envelope& out) {
  using Steady = std::chrono::steady_clock;
  using std::chrono::milliseconds;
  // The deadline: the idle limit until a frame begins, then the message limit.
  bool begun = decoder_.buffered() > 0;
  auto since = Steady::now();
  while (true) {
    switch (decoder_.next(out)) {
      case FrameDecoder::Status::kFrame:
        return true;
      case FrameDecoder::Status::kTooLarge:
        throw ProtocolError(wire::Error::FRAME_TOO_LARGE,
                            "a frame of " + std::to_string(decoder_.announced()) +
                                " bytes exceeds this node's --max-frame-bytes");
      case FrameDecoder::Status::kBadFrame:
        throw ProtocolError(wire::Error::BAD_FRAME, "a frame did not decode as a message");
      case FrameDecoder::Status::kNeedMore:
        break;
    }
    if (!begun && decoder_.buffered() > 0) {
      begun = true;
      since = Steady::now();
    }
    if (stop_ && stop_->load())
      throw ProtocolError(wire::Error::INTERNAL, "the node is shutting down");
    const milliseconds limit = begun ? limits_.message : limits_.idle;
    const auto left =
        std::chrono::duration_cast<milliseconds>(since + limit - Steady::now()).count();
    if (left <= 0)
      throw ProtocolError(wire::Error::TIMEOUT,
                          begun
                              ? "the master did not send the rest of its request within " +
                                    std::to_string(limit.count()) + " ms"
                              : "the master sent nothing within " + std::to_string(limit.count()) +
                                    " ms during the lock step; closing the session");
    // A blocking socket waits here (at most 100 ms: its receive timeout);
    // one that is not waits in poll.
    const ssize_t n = ::recv(fd_, buf_.data(), buf_.size(), 0);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (blocking_) continue;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(std::min<long>(left, 100))) < 0 && errno != EINTR)
        throw ProtocolError(
            wire::Error::INTERNAL,
            std::string("poll on the master's connection: ") + std::strerror(errno));
      continue;
    }
    if (n > 0) {
      decoder_.feed(buf_.data(), static_cast<std::size_t>(n));
      continue;
    }
    if (n == 0 && decoder_.buffered() == 0) return false;
    if (n == 0)
      throw ProtocolError(wire::Error::BAD_FRAME,
                          "the connection was closed in the middle of a frame (" +
                              std::to_string(decoder_.buffered()) +
                              " bytes of an unfinished frame)");
    if (errno == EINTR) continue;
    if (decoder_.buffered() == 0 && (errno == ECONNRESET || errno == EPIPE)) return false;
    throw ProtocolError(wire::Error::INTERNAL,
                        std::string("reading the master's connection: ") + std::strerror(errno));
  }
}

}  // namespace railcosim
