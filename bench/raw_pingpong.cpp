#include "raw_pingpong.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace railcosim {
namespace {

[[noreturn]] void fail(const char* call) {
  std::string what = "raw ping-pong: ";
  what += call;
  what += ": ";
  what += std::strerror(errno);
  throw std::runtime_error(what);
}

void no_delay(int fd) {
  const int one = 1;
  if (::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one) != 0) fail("setsockopt");
}

// Reads exactly n bytes; false at end of stream or on an error.
bool read_all(int fd, char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t got = ::recv(fd, p, n, 0);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    p += got;
    n -= static_cast<std::size_t>(got);
  }
  return true;
}

bool write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t sent = ::send(fd, p, n, MSG_NOSIGNAL);
    if (sent < 0 && errno == EINTR) continue;
    if (sent <= 0) return false;
    p += sent;
    n -= static_cast<std::size_t>(sent);
  }
  return true;
}

// The child: answers every request of `request` bytes with `reply` bytes
// until the parent closes. Uses only system calls (it was forked).
[[noreturn]] void echo(int listener, std::vector<char>& request, const std::vector<char>& reply) {
  const int fd = ::accept(listener, nullptr, nullptr);
  if (fd < 0) ::_exit(1);
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  while (read_all(fd, request.data(), request.size()))
    if (!write_all(fd, reply.data(), reply.size())) break;
  ::_exit(0);
}

}  // namespace

RawRoundTrip raw_round_trip(std::size_t request_bytes, std::size_t reply_bytes, int samples) {
  const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listener < 0) fail("socket");
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (::bind(listener, reinterpret_cast<sockaddr*>(&a), len) != 0) fail("bind");
  if (::listen(listener, 1) != 0) fail("listen");
  if (::getsockname(listener, reinterpret_cast<sockaddr*>(&a), &len) != 0) fail("getsockname");
  std::vector<char> request(request_bytes, 'q'), reply(reply_bytes, 'r');
  const pid_t child = ::fork();
  if (child < 0) fail("fork");
  if (child == 0) echo(listener, request, reply);
  ::close(listener);
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) fail("socket");
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) fail("connect");
  no_delay(fd);
  std::vector<double> t;
  t.reserve(static_cast<std::size_t>(samples));
  constexpr int kWarmUp = 200;
  for (int i = 0; i < kWarmUp + samples; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!write_all(fd, request.data(), request.size())) fail("send");
    if (!read_all(fd, reply.data(), reply.size())) fail("recv");
    if (i >= kWarmUp)
      t.push_back(
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  ::close(fd);
  int status = 0;
  ::waitpid(child, &status, 0);
  std::sort(t.begin(), t.end());
  RawRoundTrip r;
  r.request_bytes = request_bytes;
  r.reply_bytes = reply_bytes;
  r.samples = samples;
  r.p10_us = t[t.size() / 10];
  r.median_us = t[t.size() / 2];
  r.p90_us = t[t.size() * 9 / 10];
  return r;
}

}  // namespace railcosim
