// A TCP peer with one scripted exchange, for tests of what a channel or a
// remote participant does with a peer that misbehaves: it accepts one
// connection, reads one chunk (the hello), writes `reply` (nothing if empty),
// then hangs up at once or waits for the other side to hang up.
#pragma once

#include <utility>  // before Asio: its headers use std::exchange

#include <boost/asio.hpp>
#include <string>
#include <thread>

#include "connection.hpp"

namespace railcosim::test {

class OneShotPeer {
 public:
  enum class After { kHangUp, kWait };

  explicit OneShotPeer(std::string reply, After after = After::kWait)
      : reply_(std::move(reply)), after_(after), acceptor_(io_) {
    using boost::asio::ip::tcp;
    acceptor_.open(tcp::v4());
    acceptor_.bind({boost::asio::ip::make_address("127.0.0.1"), 0});
    acceptor_.listen();
    thread_ = std::thread([this] { serve(); });
  }
  ~OneShotPeer() {
    boost::system::error_code ec;
    acceptor_.close(ec);
    thread_.join();
  }
  OneShotPeer(const OneShotPeer&) = delete;
  OneShotPeer& operator=(const OneShotPeer&) = delete;

  Address address() const { return {"127.0.0.1", acceptor_.local_endpoint().port()}; }

 private:
  void serve() {
    boost::system::error_code ec;
    boost::asio::ip::tcp::socket s(io_);
    acceptor_.accept(s, ec);
    if (ec) return;
    char buf[4096];
    s.read_some(boost::asio::buffer(buf), ec);
    if (!ec && !reply_.empty()) boost::asio::write(s, boost::asio::buffer(reply_), ec);
    while (!ec && after_ == After::kWait) s.read_some(boost::asio::buffer(buf), ec);
    s.close(ec);
  }

  std::string reply_;
  After after_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::thread thread_;
};

}  // namespace railcosim::test
