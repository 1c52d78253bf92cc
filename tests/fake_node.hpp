// A node that lies, for the master's tests: a real NodeSession behind a
// plain blocking socket, whose replies a test may edit before they leave,
// and send whole or one byte at a time.
#pragma once

#include <utility>  // before Asio: its headers use std::exchange

#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <boost/asio.hpp>
#include <chrono>
#include <functional>
#include <thread>

#include "connection.hpp"
#include "session.hpp"
#include "wire.hpp"

namespace railcosim::test {

class FakeNode {
 public:
  // Edits a reply before it is sent; returns true to drip it (one byte per
  // drip interval) instead of sending it whole.
  using Edit = std::function<bool(const wire::Envelope& request, wire::Envelope& reply)>;

  // The direct data plane: a window's report frames go through this, which
  // sends them on the socket `fd` as it likes (whole, dripped, or not at
  // all) and should return soon once `stop` is set. Unset: the node does not
  // offer the direct data plane.
  using Reports =
      std::function<void(int fd, const std::string& frame, const std::atomic<bool>& stop)>;

  FakeNode(std::string role, Edit edit, std::chrono::milliseconds drip = {}, Reports reports = {})
      : edit_(std::move(edit)), drip_(drip), reports_(std::move(reports)), acceptor_(io_) {
    options_.role = std::move(role);
    options_.name = "fake_node";
    using boost::asio::ip::tcp;
    const tcp::endpoint ep(boost::asio::ip::make_address("127.0.0.1"), 0);
    acceptor_.open(ep.protocol());
    acceptor_.bind(ep);
    acceptor_.listen();
    address_ = Address{"127.0.0.1", acceptor_.local_endpoint().port()};
    thread_ = std::thread([this] { serve(); });
  }
  ~FakeNode() {
    stop_ = true;
    ::shutdown(acceptor_.native_handle(), SHUT_RDWR);
    if (const int fd = session_fd_.load(); fd >= 0) ::shutdown(fd, SHUT_RDWR);
    thread_.join();
  }
  const Address& address() const { return address_; }
  // Set once a reply has started to drip.
  bool dripping() const { return dripping_; }

 private:
  void serve() {
    while (!stop_) {
      boost::asio::ip::tcp::socket s(io_);
      boost::system::error_code ec;
      acceptor_.accept(s, ec);
      if (ec) return;
      session_fd_ = s.native_handle();
      serve_session(s);
      session_fd_ = -1;
    }
  }

  void serve_session(boost::asio::ip::tcp::socket& s) {
    NodeSession session(options_);
    if (reports_) {
      const int fd = s.native_handle();
      session.set_report_sink([this, fd](const std::string& frame) { reports_(fd, frame, stop_); });
      session.set_master_gone([this, fd] {
        pollfd p{fd, POLLRDHUP, 0};
        return stop_ || (::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP)) != 0);
      });
    }
    FrameDecoder decoder;
    std::array<char, 65536> buf{};
    boost::system::error_code ec;
    while (!stop_) {
      const std::size_t n = s.read_some(boost::asio::buffer(buf), ec);
      if (ec) return;
      decoder.feed(buf.data(), n);
      wire::Envelope req;
      while (decoder.next(req) == FrameDecoder::Status::kFrame) {
        bool close = false;
        wire::Envelope reply = session.handle(req, close);
        const bool drip = edit_ && edit_(req, reply);
        const std::string frame = encode_frame(reply);
        if (!drip) {
          boost::asio::write(s, boost::asio::buffer(frame), ec);
        } else {
          dripping_ = true;
          for (std::size_t k = 0; k < frame.size() && !stop_ && !ec; ++k) {
            boost::asio::write(s, boost::asio::buffer(&frame[k], 1), ec);
            std::this_thread::sleep_for(drip_);
          }
        }
        if (ec || close) return;
      }
    }
  }

  NodeOptions options_;
  Edit edit_;
  std::chrono::milliseconds drip_;
  Reports reports_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  Address address_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> dripping_{false};
  std::atomic<int> session_fd_{-1};
  std::thread thread_;
};

}  // namespace railcosim::test
