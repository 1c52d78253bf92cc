#include "fd_channel.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace railcosim {
namespace {

std::string ms_text(std::chrono::milliseconds t) {
  return std::to_string(t.count()) + " ms";
}

}  // namespace

FdChannel::FdChannel(int fd, std::string what, std::size_t max_frame_bytes)
    : fd_(fd),
      what_(std::move(what)),
      max_frame_bytes_(max_frame_bytes),
      decoder_(max_frame_bytes),
      buffer_(65536) {
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
  const int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

FdChannel::~FdChannel() {
  if (fd_ >= 0) ::close(fd_);
}

void FdChannel::set_timeout(int option, std::chrono::milliseconds timeout,
                            std::chrono::milliseconds& now) {
  if (timeout == now) return;
  timeval tv{};
  tv.tv_sec = static_cast<time_t>(timeout.count() / 1000);
  tv.tv_usec = static_cast<suseconds_t>((timeout.count() % 1000) * 1000);
  if (::setsockopt(fd_, SOL_SOCKET, option, &tv, sizeof tv) != 0)
    throw LinkError(LinkError::Kind::kIo,
                    "cannot set a deadline on the link to " + what_ + ": " + std::strerror(errno));
  now = timeout;
}

void FdChannel::send(const wire::Envelope& envelope, std::chrono::milliseconds timeout) {
  send_frame(encode_frame(envelope, max_frame_bytes_), timeout);
}

void FdChannel::send_frame(const std::string& frame, std::chrono::milliseconds timeout) {
  // The socket blocks; its send timeout makes a stuck send return, and
  // write_all's deadline decides.
  set_timeout(SO_SNDTIMEO, timeout, send_timeout_);
  write_all(fd_, frame, timeout, what_);
}

wire::Envelope FdChannel::receive(std::chrono::milliseconds timeout) {
  wire::Envelope out;
  while (true) {
    switch (decoder_.next(out)) {
      case FrameDecoder::Status::kFrame:
        return out;
      case FrameDecoder::Status::kTooLarge:
        throw LinkError(LinkError::Kind::kProtocol, what_ + " sent a frame over the size limit (" +
                                                        std::to_string(decoder_.announced()) +
                                                        " bytes)");
      case FrameDecoder::Status::kBadFrame:
        throw LinkError(LinkError::Kind::kProtocol, what_ + " sent a frame that is not a message");
      case FrameDecoder::Status::kNeedMore:
        break;
    }
    set_timeout(SO_RCVTIMEO, timeout, recv_timeout_);
    const ssize_t n = ::recv(fd_, buffer_.data(), buffer_.size(), 0);
    if (n > 0) {
      decoder_.feed(buffer_.data(), static_cast<std::size_t>(n));
      continue;
    }
    if (n == 0) {
      std::string why = what_;
      why += " closed the link";
      if (decoder_.buffered() > 0) why += " in the middle of a frame";
      throw LinkError(LinkError::Kind::kClosed, why);
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK)
      throw LinkError(LinkError::Kind::kTimeout,
                      what_ + " sent nothing within " + ms_text(timeout));
    std::string why = "cannot read from ";
    why += what_;
    why += ": ";
    why += std::strerror(errno);
    throw LinkError(errno == ECONNRESET ? LinkError::Kind::kClosed : LinkError::Kind::kIo, why);
  }
}

void write_all(int fd, const std::string& bytes, std::chrono::milliseconds timeout,
               const std::string& what) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      pollfd p{fd, POLLOUT, 0};
      if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) == 0)
        throw LinkError(LinkError::Kind::kTimeout,
                        what + " did not read what it was sent within " + ms_text(timeout));
      continue;
    }
    std::string why = "cannot send to ";
    why += what;
    why += ": ";
    why += (errno == EPIPE || errno == ECONNRESET) ? "the link is closed" : std::strerror(errno);
    throw LinkError(LinkError::Kind::kClosed, why);
  }
}

}  // namespace railcosim
