// The TCP server both node programs run: one session at a time, any number of
// sessions one after another, until stopped.
#pragma once

#include <utility>  // before Asio: its headers use std::exchange

#include <atomic>
#include <boost/asio.hpp>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "connection.hpp"
#include "session.hpp"

namespace railcosim {

// Every limit is a deadline for a whole message or a whole piece of work:
// bytes that trickle in do not extend it.
struct ServerLimits {
  // Frames in either direction; a reply over it becomes a FRAME_TOO_LARGE
  // error reply.
  std::size_t max_frame_bytes = kDefaultMaxFrameBytes;
  // A session that sends nothing between requests for this long is closed (TIMEOUT).
  std::chrono::milliseconds idle_timeout{60000};
  // A peer that connects must complete the hello (and the authentication)
  // this fast after connecting.
  std::chrono::milliseconds handshake_timeout{10000};
  // A request, once begun, must arrive whole this fast; a reply must be read
  // whole this fast (a peer that does not read is dropped).
  std::chrono::milliseconds message_timeout{10000};
  // The work of one request (a macro step) may take this long; beyond it the
  // step fails (STEP_FAILED).
  std::chrono::milliseconds max_step_time{30000};
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
  // A connection's hello (and authentication) completed: true when it now
  // holds the session, false when another one got there first (it is then
  // answered BUSY).
  bool opened(Conn* c);
  void session_ended(Conn* c);
  // Runs `job` on the worker thread (one job at a time, in order).
  void run_on_worker(std::function<void()> job);
  void work();

  NodeOptions options_;
  ServerLimits limits_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<Conn> active_;
  // Connections still in their hello, each within the handshake deadline,
  // side by side: a client that says hello and stays silent holds nobody.
  std::vector<std::shared_ptr<Conn>> opening_;
  static constexpr std::size_t kMaxOpenings = 8;
  long sessions_ = 0;
  std::atomic<bool> stopping_{false};  // cancels the work running on the worker
  std::mutex jobs_mutex_;
  std::condition_variable jobs_cv_;
  std::deque<std::function<void()>> jobs_;
  bool quit_ = false;
  std::thread worker_;  // last: joined before anything above is destroyed
};

// A node program: its name (in messages and logs), the participant it serves
// unless --role says otherwise, and how it builds that participant: an
// outside participant sets `configure`, called once per session with its
// ParticipantSetup (interfaces, run settings, its own configuration from
// --config or the master's scene); the product's own node programs leave
// it empty and build the product's model (`make_participant`, or the
// built-in one when that is empty too).
struct NodeProgram {
  std::string name;                     // e.g. "soil_node"
  std::string default_role;             // vehicle, track, rail, soil or any
  ParticipantBuilder make_participant;  // from the product's scene; empty: the built-in model
  SetupBuilder configure;               // set: takes precedence, the scene is not read
};

// The whole program of a node: parses the command line, prints
// "listening on HOST:PORT" on stdout, serves until SIGINT/SIGTERM. This is
// the entry point of a participant written against the installed package
// (docs/participant-guide-cpp.md): its main() calls node_main with its own
// NodeProgram.
int node_main(const NodeProgram& program, int argc, char** argv);
// The built-in node programs: the built-in model of `default_role`.
int node_main(const std::string& default_role, int argc, char** argv);

}  // namespace railcosim
