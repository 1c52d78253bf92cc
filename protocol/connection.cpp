#include "connection.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

namespace railcosim {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

std::atomic<const std::atomic<int>*> g_interrupt{nullptr};

// The signal that asks to stop, or 0.
int interrupted() {
  const std::atomic<int>* flag = g_interrupt.load();
  return flag ? flag->load() : 0;
}

}  // namespace

void set_interrupt_flag(const std::atomic<int>* flag) {
  g_interrupt.store(flag);
}

int interrupt_signal() {
  return interrupted();
}

Address parse_address(const std::string& text, const std::string& what) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos)
    throw std::invalid_argument(what + " '" + text + "': expected HOST:PORT");
  Address a;
  std::string host = text.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  if (!host.empty()) a.host = host;
  const std::string port = text.substr(colon + 1);
  char* end = nullptr;
  const long p = std::strtol(port.c_str(), &end, 10);
  if (port.empty() || *end != '\0' || p < 0 || p > 65535)
    throw std::invalid_argument(what + " '" + text +
                                "': the port must be a number from 0 to 65535");
  a.port = static_cast<std::uint16_t>(p);
  return a;
}

Connection::Connection(Address peer) : peer_(std::move(peer)), socket_(io_), decoder_(max_frame_) {}

Connection::~Connection() {
  close();
}

bool Connection::next_buffered(wire::Envelope& out) {
  switch (decoder_.next(out)) {
    case FrameDecoder::Status::kFrame:
      return true;
    case FrameDecoder::Status::kNeedMore:
      return false;
    case FrameDecoder::Status::kTooLarge:
      throw NetError(NetError::Kind::kProtocol,
                     peer_.str() + " sent a frame over the size limit (" +
                         std::to_string(decoder_.announced()) + " bytes)");
    case FrameDecoder::Status::kBadFrame:
      break;
  }
  throw NetError(NetError::Kind::kProtocol, peer_.str() + " sent a frame that is not a message");
}

bool Connection::read_now() {
  while (true) {
    const ssize_t n = ::recv(socket_.native_handle(), buffer_.data(), buffer_.size(), MSG_DONTWAIT);
    if (n > 0) {
      decoder_.feed(buffer_.data(), static_cast<std::size_t>(n));
      return true;
    }
    if (n == 0) return false;
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
    if (errno == ECONNRESET) return false;
    throw NetError(NetError::Kind::kIo,
                   "cannot read from " + peer_.str() + ": " + std::strerror(errno));
  }
}

int Connection::release_fd() {
  if (!socket_.is_open()) return -1;
  const int fd = ::dup(socket_.native_handle());
  boost::system::error_code ec;
  socket_.close(ec);
  return fd;
}

void Connection::use_blocking_io() {
  const int fd = socket_.native_handle();
  boost::system::error_code ec;
  socket_.native_non_blocking(false, ec);
  timeval poll{};
  poll.tv_usec = std::chrono::duration_cast<std::chrono::microseconds>(kInterruptPoll).count();
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &poll, sizeof poll);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &poll, sizeof poll);
}

void Connection::shutdown_send() {
  boost::system::error_code ec;
  socket_.shutdown(tcp::socket::shutdown_send, ec);
}

void Connection::close() {
  boost::system::error_code ec;
  if (socket_.is_open()) {
    socket_.shutdown(tcp::socket::shutdown_both, ec);
    socket_.close(ec);
  }
}

std::unique_ptr<Connection> Connection::connect(const Address& address, Duration timeout) {
  auto c = std::unique_ptr<Connection>(new Connection(address));
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto pause = Duration(20);
  std::string last = "no attempt";
  while (true) {
    boost::system::error_code ec;
    const auto ip = asio::ip::make_address(address.host, ec);
    tcp::resolver::results_type endpoints;
    if (ec) {
      tcp::resolver resolver(c->io_);
      endpoints = resolver.resolve(address.host, std::to_string(address.port), ec);
      if (ec)
        throw NetError(NetError::Kind::kConnect,
                       "cannot resolve " + address.str() + ": " + ec.message());
    }
    c->socket_ = tcp::socket(c->io_);
    if (!ec && endpoints.empty())
      c->socket_.connect(tcp::endpoint(ip, address.port), ec);
    else
      asio::connect(c->socket_, endpoints, ec);
    if (!ec) {
      c->socket_.set_option(tcp::no_delay(true), ec);
      c->use_blocking_io();
      return c;
    }
    last = ec.message();
    if (const int sig = interrupted())
      throw NetError(NetError::Kind::kInterrupted, "interrupted by signal " + std::to_string(sig) +
                                                       " while connecting to " + address.str());
    if (std::chrono::steady_clock::now() + pause > deadline) break;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, Duration(500));
  }
  throw NetError(NetError::Kind::kConnect, "cannot connect to " + address.str() + ": " + last +
                                               " (gave up after " +
                                               std::to_string(timeout.count()) + " ms)");
}

namespace {

// Milliseconds left before `deadline`, rounded up (poll() takes whole ms).
int ms_left(Clock::time_point deadline, Clock::time_point now) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - now);
  return static_cast<int>(std::max<std::int64_t>(0, left.count()));
}

// Before a blocking call that must not outlast `deadline`: when less than
// one interrupt poll is left, waits for the socket with poll() (the socket's
// own timeouts are one kInterruptPoll). False when the socket is not ready.
bool ready_in_time(int fd, short events, Clock::time_point deadline, Clock::time_point now) {
  if (deadline - now >= kInterruptPoll) return true;
  pollfd p{fd, events, 0};
  return ::poll(&p, 1, ms_left(deadline, now)) > 0;
}

bool try_again(int error) {
  return error == EAGAIN || error == EWOULDBLOCK || error == EINTR;
}

}  // namespace

void Connection::check_wait(Clock::time_point deadline, Duration timeout, const char* what) const {
  if (const int sig = interrupted())
    throw NetError(NetError::Kind::kInterrupted, "interrupted by signal " + std::to_string(sig));
  if (Clock::now() >= deadline)
    throw NetError(NetError::Kind::kTimeout, std::string("no ") + what + " within " +
                                                 std::to_string(timeout.count()) + " ms");
}

void Connection::send(const wire::Envelope& envelope, Duration timeout) {
  send_raw(encode_frame(envelope, max_frame_), timeout);
}

// A blocking send() with the socket's send timeout of one interrupt poll:
// one system call per message when the kernel takes it at once, as it does
// unless the peer has stopped reading.
void Connection::send_raw(const std::string& bytes, Duration timeout) {
  const auto deadline = Clock::now() + timeout;
  const int fd = socket_.native_handle();
  std::size_t done = 0;
  while (done < bytes.size()) {
    check_wait(deadline, timeout, "write completion");
    if (!ready_in_time(fd, POLLOUT, deadline, Clock::now())) continue;
    const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n >= 0) {
      done += static_cast<std::size_t>(n);
    } else if (!try_again(errno)) {
      throw NetError(NetError::Kind::kClosed, std::string("cannot send: ") + std::strerror(errno));
    }
  }
}

// A blocking recv() with the socket's receive timeout of one interrupt poll
// (so the stop flag and the deadline are looked at at least that often): one
// system call per read that finds data, none that must fail.
wire::Envelope Connection::receive(Duration timeout) {
  // One deadline for the whole frame, however it is cut into reads.
  const auto deadline = Clock::now() + timeout;
  const int fd = socket_.native_handle();
  wire::Envelope e;
  while (true) {
    switch (decoder_.next(e)) {
      case FrameDecoder::Status::kFrame:
        return e;
      case FrameDecoder::Status::kTooLarge:
        throw NetError(NetError::Kind::kProtocol,
                       "the peer announced a frame of " + std::to_string(decoder_.announced()) +
                           " bytes, over the limit of " + std::to_string(max_frame_));
      case FrameDecoder::Status::kBadFrame:
        throw NetError(NetError::Kind::kProtocol, "the peer sent a frame that is not a message");
      case FrameDecoder::Status::kNeedMore:
        break;
    }
    check_wait(deadline, timeout, "reply");
    if (!ready_in_time(fd, POLLIN, deadline, Clock::now())) continue;
    const ssize_t n = ::recv(fd, buffer_.data(), buffer_.size(), 0);
    if (n > 0) {
      decoder_.feed(buffer_.data(), static_cast<std::size_t>(n));
    } else if (n == 0 || errno == ECONNRESET) {
      throw NetError(NetError::Kind::kClosed,
                     decoder_.buffered() ? "the peer closed the connection in the middle of a frame"
                                         : "the peer closed the connection");
    } else if (!try_again(errno)) {
      throw NetError(NetError::Kind::kIo, std::string("cannot read: ") + std::strerror(errno));
    }
  }
}

}  // namespace railcosim
