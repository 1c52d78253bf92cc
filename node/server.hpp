// The TCP server both node programs run: one session at a time, any number of
// sessions one after another, until stopped.
#pragma once

#include <utility>  // before Asio: its headers use std::exchange

#include <boost/asio.hpp>
#include <chrono>
#include <memory>

#include "connection.hpp"
#include "session.hpp"

namespace railcosim {

struct ServerLimits {
  std::size_t max_frame_bytes = kDefaultMaxFrameBytes;
  // A session that sends nothing for this long is closed (TIMEOUT).
  std::chrono::milliseconds idle_timeout{60000};
  // A peer that connects must complete the hello this fast.
  std::chrono::milliseconds handshake_timeout{10000};
};

class NodeServer {
 public:
  // Binds at once (port 0: the system chooses); throws std::runtime_error
  // naming the address if it cannot.
  NodeServer(NodeOptions options, const Address& listen, ServerLimits limits = {});
  ~NodeServer();

  // The address actually bound.
  Address local_address() const;
  // Serves until stop(). Stops on SIGINT/SIGTERM when handle_signals is set.
  void run(bool handle_signals);
  // Thread-safe.
  void stop();
  // Sessions served so far (finished or not), for tests and logs.
  long sessions() const { return sessions_; }

 private:
  class Conn;
  void accept();
  void session_ended(Conn* c);

  NodeOptions options_;
  ServerLimits limits_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<Conn> active_;
  long sessions_ = 0;
};

// The whole program of a node: parses the command line, prints
// "listening on HOST:PORT" on stdout, serves until SIGINT/SIGTERM.
int node_main(const std::string& default_role, int argc, char** argv);

}  // namespace railcosim
