#include "server.hpp"

#include <CLI/CLI.hpp>
#include <array>
#include <cstdio>
#include <deque>

#include "auth.hpp"
#include "log.hpp"

namespace railcosim {

namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

std::string endpoint_text(const tcp::socket& s) {
  boost::system::error_code ec;
  const auto ep = s.remote_endpoint(ec);
  if (ec) return "unknown peer";
  return ep.address().to_string() + ":" + std::to_string(ep.port());
}

const std::string& component(const std::string& role) {
  return role;
}

}  // namespace

// One accepted connection. Reads frames, hands them to the session, writes
// the replies in order; ends the session on error, shutdown or EOF.
class NodeServer::Conn : public std::enable_shared_from_this<Conn> {
 public:
  Conn(NodeServer& server, tcp::socket socket)
      : server_(server),
        socket_(std::move(socket)),
        peer_(endpoint_text(socket_)),
        decoder_(server.limits_.max_frame_bytes),
        session_(server.options_),
        log_(logger(component(server.options_.role))),
        idle_(socket_.get_executor()) {}

  void start() {
    boost::system::error_code ec;
    socket_.set_option(tcp::no_delay(true), ec);
    log_->info("session {} from {} started", server_.sessions_, peer_);
    arm_idle_timer(server_.limits_.handshake_timeout, "complete the hello");
    read();
  }

  // Refuses a connection that arrived while another session runs.
  void refuse_busy(const std::string& active_peer) {
    closing_ = true;
    queue(encode_frame(error_envelope(0, wire::Error::BUSY,
                                      "this node already serves a session (from " + active_peer +
                                          "); try again when it has ended")));
  }

  const std::string& peer() const { return peer_; }

  void close() {
    boost::system::error_code ec;
    socket_.shutdown(tcp::socket::shutdown_both, ec);
    socket_.close(ec);
  }

 private:
  void read() {
    auto self = shared_from_this();
    socket_.async_read_some(asio::buffer(buf_), [this, self](boost::system::error_code ec,
                                                             std::size_t n) {
      if (ec) {
        if (ec == asio::error::eof && decoder_.buffered() > 0) {
          // The peer stopped sending inside a frame: say so before closing.
          fail(wire::Error::BAD_FRAME, "the connection was closed in the middle of a frame (" +
                                           std::to_string(decoder_.buffered()) +
                                           " bytes of an unfinished frame)");
          return;
        }
        if (ec != asio::error::operation_aborted)
          log_->info("session from {} ended by the peer ({}) at macro step {}", peer_,
                     ec == asio::error::eof ? "connection closed" : ec.message(), session_.step());
        finish();
        return;
      }
      decoder_.feed(buf_.data(), n);
      if (!drain()) return;
      arm_idle_timer(said_hello_ ? server_.limits_.idle_timeout : server_.limits_.handshake_timeout,
                     said_hello_ ? "send anything" : "complete the hello");
      read();
    });
  }

  // Handles every complete frame; false once the session is over.
  bool drain() {
    wire::Envelope req;
    while (true) {
      const auto st = decoder_.next(req);
      if (st == FrameDecoder::Status::kNeedMore) return true;
      if (st == FrameDecoder::Status::kTooLarge) {
        fail(wire::Error::FRAME_TOO_LARGE, "a frame of " + std::to_string(decoder_.announced()) +
                                               " bytes exceeds the limit of " +
                                               std::to_string(server_.limits_.max_frame_bytes));
        return false;
      }
      if (st == FrameDecoder::Status::kBadFrame) {
        fail(wire::Error::BAD_FRAME, "a frame did not decode as a message");
        return false;
      }
      bool close = false;
      const wire::Envelope reply = session_.handle(req, close);
      if (reply.has_hello_reply()) said_hello_ = true;
      if (reply.has_error())
        log_->warn("session from {}: {} rejected at macro step {}: {}", peer_, body_name(req),
                   session_.step(), reply.error().message());
      else if (req.has_step())
        log_->debug("{} macro step {} (t = {} s) done", session_.description(), req.step().step(),
                    req.step().t());
      else if (req.has_configure())
        log_->info("session from {} configured: {}", peer_, session_.description());
      if (close) {
        // Free the node for the next session before the reply leaves, so a
        // client that got this reply can connect again at once.
        closing_ = true;
        server_.session_ended(this);
      }
      queue(encode_frame(reply, server_.limits_.max_frame_bytes));
      if (close) return false;
    }
  }

  // (Re)starts the deadline by which the peer must have sent something.
  void arm_idle_timer(std::chrono::milliseconds limit, const char* what) {
    idle_.expires_after(limit);
    auto self = shared_from_this();
    idle_.async_wait([this, self, limit, what](boost::system::error_code ec) {
      if (ec || finished_ || closing_) return;
      fail(wire::Error::TIMEOUT, std::string("the peer did not ") + what + " within " +
                                     std::to_string(limit.count()) + " ms; closing the session");
    });
  }

  void fail(wire::Error::Code code, const std::string& message) {
    log_->warn("session from {}: {}; closing it", peer_, message);
    closing_ = true;
    server_.session_ended(this);
    queue(encode_frame(error_envelope(0, code, message, session_.step())));
  }

  void queue(std::string frame) {
    out_.push_back(std::move(frame));
    if (!writing_) write();
  }

  void write() {
    writing_ = true;
    auto self = shared_from_this();
    asio::async_write(socket_, asio::buffer(out_.front()),
                      [this, self](boost::system::error_code ec, std::size_t) {
                        out_.pop_front();
                        if (ec) {
                          writing_ = false;
                          finish();
                          return;
                        }
                        if (!out_.empty()) {
                          write();
                          return;
                        }
                        writing_ = false;
                        if (closing_) finish();
                      });
  }

  void finish() {
    if (finished_) return;
    finished_ = true;
    idle_.cancel();
    close();
    server_.session_ended(this);
  }

  NodeServer& server_;
  tcp::socket socket_;
  std::string peer_;
  FrameDecoder decoder_;
  NodeSession session_;
  std::shared_ptr<spdlog::logger> log_;
  std::array<char, 65536> buf_{};
  std::deque<std::string> out_;
  bool writing_ = false;
  bool closing_ = false;
  bool finished_ = false;
  bool said_hello_ = false;
  asio::steady_timer idle_;
};

NodeServer::NodeServer(NodeOptions options, const Address& listen, ServerLimits limits)
    : options_(std::move(options)), limits_(limits), acceptor_(io_) {
  boost::system::error_code ec;
  const auto ip = asio::ip::make_address(listen.host, ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + listen.str() + ": '" + listen.host +
                             "' is not an IP address");
  const tcp::endpoint ep(ip, listen.port);
  acceptor_.open(ep.protocol(), ec);
  if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(ep, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error("cannot listen on " + listen.str() + ": " + ec.message());
}

NodeServer::~NodeServer() = default;

Address NodeServer::local_address() const {
  const auto ep = acceptor_.local_endpoint();
  return Address{ep.address().to_string(), ep.port()};
}

void NodeServer::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec) {
      if (ec != asio::error::operation_aborted) accept();
      return;
    }
    auto conn = std::make_shared<Conn>(*this, std::move(socket));
    if (active_) {
      logger(component(options_.role))
          ->warn("refused a connection from {}: busy with the session from {}", conn->peer(),
                 active_->peer());
      conn->refuse_busy(active_->peer());
    } else {
      active_ = conn;
      ++sessions_;
      conn->start();
    }
    accept();
  });
}

void NodeServer::session_ended(Conn* c) {
  if (active_.get() == c) active_.reset();
}

void NodeServer::run(bool handle_signals) {
  asio::signal_set signals(io_);
  if (handle_signals) {
    signals.add(SIGINT);
    signals.add(SIGTERM);
    signals.async_wait([this](boost::system::error_code ec, int sig) {
      if (ec) return;
      logger(component(options_.role))->info("signal {} received: stopping", sig);
      stop();
    });
  }
  accept();
  io_.run();
}

void NodeServer::stop() {
  asio::post(io_, [this] {
    boost::system::error_code ec;
    acceptor_.close(ec);
    if (active_) active_->close();
    io_.stop();
  });
}

int node_main(const std::string& default_role, int argc, char** argv) {
  std::string role = default_role;
  CLI::App app{"Serves the " + default_role +
               " participant of a vehicle/track/soil co-simulation to a master, one session at a "
               "time."};
  std::string listen = "127.0.0.1:0";
  app.add_option("--role", role,
                 "The participant this node serves: vehicle, track, rail, soil, or any (whatever "
                 "the master asks for)")
      ->check(CLI::IsMember({"vehicle", "track", "rail", "soil", "any"}))
      ->capture_default_str();
  std::string scene_path;
  std::size_t max_frame = kDefaultMaxFrameBytes;
  std::string level = "info";
  double idle_seconds = 60.0;
  long max_micro_steps = Newmark::kMaxStepsPerInterval;
  std::string token_file;
  app.add_option("--listen", listen, "HOST:PORT to listen on (port 0: the system chooses)")
      ->capture_default_str();
  app.add_option("--scene", scene_path,
                 "Scene file: when given, only a master running this very scene is accepted")
      ->check(CLI::ExistingFile);
  app.add_option("--max-frame-bytes", max_frame, "Largest frame accepted")->capture_default_str();
  app.add_option("--token-file", token_file,
                 "File holding a shared secret (16+ characters): a master must prove it knows it "
                 "before anything else. Required to listen on a non-loopback address")
      ->check(CLI::ExistingFile);
  app.add_option("--max-micro-steps", max_micro_steps,
                 "Micro steps a subsystem may take in one macro step before it gives up "
                 "(STEP_FAILED: the run diverges)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--idle-timeout", idle_seconds,
                 "Seconds a session may stay silent before the node closes it")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--log-level", level, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  spdlog::set_level(spdlog::level::from_str(level));
  const std::string who = default_role;
  try {
    NodeOptions options;
    options.role = role;
    options.name = who + "_node";
    options.max_micro_steps = max_micro_steps;
    if (!scene_path.empty()) options.pinned_scene = load_scene(scene_path);
    const Address address = parse_address(listen, "--listen");
    if (!token_file.empty()) options.token = read_token_file(token_file);
    if (!options.token && !is_loopback(address.host))
      throw std::runtime_error(
          "refusing to listen on " + address.str() +
          " without --token-file: any host that reaches this address could drive the node. "
          "Share a secret with the master (--token-file on both), or listen on 127.0.0.1");
    ServerLimits limits;
    limits.max_frame_bytes = max_frame;
    limits.idle_timeout = std::chrono::milliseconds(static_cast<long>(idle_seconds * 1000));
    limits.handshake_timeout = std::min(limits.handshake_timeout, limits.idle_timeout);
    NodeServer server(options, address, limits);
    std::printf("listening on %s\n", server.local_address().str().c_str());
    std::fflush(stdout);
    server.run(true);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s_node: %s\n", who.c_str(), e.what());
    return 2;
  }
}

}  // namespace railcosim
