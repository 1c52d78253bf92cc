// The server's side of one accepted connection (internal to server.cpp):
// the session's event-driven reads and writes, its deadlines, and the hand
// over of long requests to the worker thread.
#pragma once

#include <poll.h>
#include <unistd.h>

#include <array>
#include <cstdio>

#include "fd_channel.hpp"
#include "frame_source.hpp"
#include "log.hpp"
#include "server.hpp"
#include "work_budget.hpp"

namespace railcosim {

namespace asio = boost::asio;
using asio::ip::tcp;

inline std::string endpoint_text(const tcp::socket& s) {
  boost::system::error_code ec;
  const auto ep = s.remote_endpoint(ec);
  if (ec) return "unknown peer";
  return ep.address().to_string() + ":" + std::to_string(ep.port());
}

// One accepted connection. Reads a frame, hands it to the session (the long
// requests on the server's worker thread, so that the node still answers
// signals and turns other clients away meanwhile), writes its reply, and only
// then reads on: a peer that does not read its replies stops being read
// (backpressure), so a session holds at most one request and one reply.
// Every wait is a deadline for a whole message (see ServerLimits).
class NodeServer::Conn : public std::enable_shared_from_this<Conn> {
 public:
  Conn(NodeServer& server, tcp::socket socket)
      : server_(server),
        socket_(std::move(socket)),
        peer_(endpoint_text(socket_)),
        decoder_(server.limits_.max_frame_bytes),
        source_(socket_.native_handle(), decoder_,
                {server.limits_.idle_timeout, server.limits_.message_timeout}, &server.stopping_),
        session_(server.options_),
        log_(logger(server.options_.role)),
        deadline_(socket_.get_executor()) {
    // A window's step reports are written by the worker while this
    // connection waits for the window's reply (nothing else writes then).
    session_.set_report_sink([this](const std::string& frame) {
      write_all(fd_, frame, server_.limits_.message_timeout, "the master at " + peer_);
    });
    session_.set_max_frame_bytes(server.limits_.max_frame_bytes);
    // A lock step reads its requests on the worker (nothing else reads then).
    session_.set_request_source([this](wire::Envelope& e) { return source_.next(e); });
    session_.set_master_gone([this] { return !socket_.is_open() || source_.hung_up(); });
    fd_ = socket_.native_handle();
  }

  const std::shared_ptr<PeerInbox>& inbox() const { return session_.inbox(); }

  void start() {
    boost::system::error_code ec;
    socket_.set_option(tcp::no_delay(true), ec);
    log_->debug("connection from {}: waiting for its hello", peer_);
    // One deadline for the whole opening, authentication included: bytes
    // that trickle in do not extend it.
    arm(server_.limits_.handshake_timeout, "complete the hello");
    pump();
  }

  // Refuses a connection that arrived while another session runs.
  // The refusal names nobody: whose session runs is not for a stranger.
  void refuse_busy() {
    closing_ = true;
    arm(server_.limits_.message_timeout, "read the refusal");
    queue(encode_frame(error_envelope(0, wire::Error::BUSY, kBusyText)));
  }

  const std::string& peer() const { return peer_; }

  void close() {
    if (released_ >= 0) ::shutdown(released_, SHUT_RDWR);  // the worker sees it and returns
    boost::system::error_code ec;
    socket_.shutdown(tcp::socket::shutdown_both, ec);
    socket_.close(ec);
  }

 private:
  // Moves the session on: handles the next buffered frame, or reads.
  void pump() {
    if (finished_ || closing_ || busy_ || writing_) return;
    wire::Envelope req;
    const auto st = decoder_.next(req);
    if (st == FrameDecoder::Status::kTooLarge) {
      fail(wire::Error::FRAME_TOO_LARGE, "a frame of " + std::to_string(decoder_.announced()) +
                                             " bytes exceeds the limit of " +
                                             std::to_string(server_.limits_.max_frame_bytes));
      return;
    }
    if (st == FrameDecoder::Status::kBadFrame) {
      fail(wire::Error::BAD_FRAME, "a frame did not decode as a message");
      return;
    }
    if (st == FrameDecoder::Status::kFrame) {
      handle(std::move(req));
      return;
    }
    // Between frames the peer may stay silent for the idle timeout; a frame
    // it has begun must arrive whole within the message timeout.
    if (said_hello_) {
      if (decoder_.buffered() == 0) {
        frame_started_ = false;
        arm(server_.limits_.idle_timeout, "send anything");
      } else if (!frame_started_) {
        frame_started_ = true;
        arm(server_.limits_.message_timeout, "send the rest of its request");
      }
    }
    read();
  }

  void read() {
    auto self = shared_from_this();
    socket_.async_read_some(asio::buffer(buf_), [this, self](boost::system::error_code ec,
                                                             std::size_t n) {
      if (finished_) return;
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
      pump();
    });
  }

  // The socket out of the event loop and back (on this thread): the worker
  // keeps using the same descriptor meanwhile.
  bool hand_over() {
    boost::system::error_code ec;
    protocol_ = socket_.local_endpoint(ec).protocol();
    if (!ec) released_ = socket_.release(ec);
    if (ec) released_ = -1;
    if (released_ >= 0) source_.set_blocking(true);
    return released_ >= 0;
  }
  void take_back() {
    source_.set_blocking(false);
    boost::system::error_code ec;
    socket_.assign(protocol_, released_, ec);
    if (ec) ::close(released_);
    released_ = -1;
    if (ec) finish();
  }

  // Requests that may take long run on the worker thread.
  static bool long_request(const wire::Envelope& req) {
    return req.has_step() || req.has_statics() || req.has_initialize() || req.has_configure() ||
           req.has_window();
  }

  void handle(wire::Envelope req) {
    frame_started_ = false;  // the next frame's deadline starts with its first byte
    if (!said_hello_ || !long_request(req)) {
      bool close = false;
      wire::Envelope reply = session_.handle(req, close);
      answer(req, std::move(reply), close);
      return;
    }
    busy_ = true;
    deadline_.cancel();  // the peer waits for us now
    // A lock step reads the socket on the worker: out of the event loop's
    // sight, lest every request wake this thread too.
    const bool bypass = req.has_window() && req.window().lockstep() && hand_over();
    auto self = shared_from_this();
    server_.run_on_worker([this, self, bypass, req = std::move(req)] {
      bool close = false;
      wire::Envelope reply;
      {
        ScopedWorkBudget budget(server_.limits_.max_step_time, &server_.stopping_);
        reply = session_.handle(req, close);
      }
      asio::post(socket_.get_executor(),
                 [this, self, bypass, req, reply = std::move(reply), close]() mutable {
                   if (bypass) take_back();
                   busy_ = false;
                   if (!finished_) answer(req, std::move(reply), close);
                 });
    });
  }

  void answer(const wire::Envelope& req, wire::Envelope reply, bool close) {
    if (reply.has_hello_reply()) {
      // The first connection whose hello completes holds the session.
      if (server_.opened(this)) {
        said_hello_ = true;
        log_->info("session {} from {} started", server_.sessions_, peer_);
      } else {
        reply = error_envelope(req.id(), wire::Error::BUSY, kBusyText);
        close = true;
      }
    }
    if (reply.has_error())
      log_->warn("session from {}: {} rejected at macro step {}: {}", peer_, body_name(req),
                 session_.step(), reply.error().message());
    else if (req.has_step())
      log_->debug("{} macro step {} (t = {} s) done", session_.description(), req.step().step(),
                  req.step().t());
    else if (req.has_configure())
      log_->info("session from {} configured: {}", peer_, session_.description());
    std::string frame;
    try {
      frame = encode_frame(reply, server_.limits_.max_frame_bytes);
    } catch (const ProtocolError& e) {
      // A reply over this node's own limit is an error reply, not a crash.
      const std::string why = "the reply to " + body_name(req) + " (" +
                              std::to_string(reply.ByteSizeLong()) +
                              " bytes) exceeds this node's --max-frame-bytes of " +
                              std::to_string(server_.limits_.max_frame_bytes);
      log_->warn("session from {}: {}; closing it", peer_, why);
      frame = encode_frame(
          error_envelope(req.id(), wire::Error::FRAME_TOO_LARGE, why, session_.step()));
      close = true;
    }
    if (close) {
      // Free the node for the next session before the reply leaves, so a
      // client that got this reply can connect again at once.
      closing_ = true;
      server_.session_ended(this);
    }
    if (said_hello_) arm(server_.limits_.message_timeout, "read the reply");
    queue(std::move(frame));
  }

  // (Re)starts the one deadline the session runs against.
  void arm(std::chrono::milliseconds limit, const char* what) {
    deadline_.expires_after(limit);
    auto self = shared_from_this();
    deadline_.async_wait([this, self, limit, what](boost::system::error_code ec) {
      if (ec || finished_ || busy_) return;
      const std::string why = std::string("the peer did not ") + what + " within " +
                              std::to_string(limit.count()) + " ms; closing the session";
      if (closing_ || writing_) {
        // It does not read what it is sent: nothing more can reach it.
        log_->warn("session from {}: {}", peer_, why);
        finish();
        return;
      }
      fail(wire::Error::TIMEOUT, why);
    });
  }

  void fail(wire::Error::Code code, const std::string& message) {
    log_->warn("session from {}: {}; closing it", peer_, message);
    closing_ = true;
    server_.session_ended(this);
    arm(server_.limits_.message_timeout, "read the error");
    queue(encode_frame(error_envelope(0, code, message, session_.step())));
  }

  void queue(std::string frame) {
    out_ = std::move(frame);
    writing_ = true;
    auto self = shared_from_this();
    asio::async_write(socket_, asio::buffer(out_),
                      [this, self](boost::system::error_code ec, std::size_t) {
                        writing_ = false;
                        out_.clear();
                        out_.shrink_to_fit();
                        if (ec || closing_) {
                          finish();
                          return;
                        }
                        pump();
                      });
  }

  void finish() {
    if (finished_) return;
    finished_ = true;
    deadline_.cancel();
    close();
    server_.session_ended(this);
  }

  NodeServer& server_;
  tcp::socket socket_;
  std::string peer_;
  int fd_ = -1;        // the socket's descriptor, for the worker
  int released_ = -1;  // the descriptor while out of the event loop
  tcp protocol_ = tcp::v4();
  FrameDecoder decoder_;
  FrameSource source_;
  NodeSession session_;
  std::shared_ptr<spdlog::logger> log_;
  std::array<char, 65536> buf_{};
  std::string out_;  // the one reply being written
  bool writing_ = false;
  bool busy_ = false;  // a request runs on the worker
  bool closing_ = false;
  bool finished_ = false;
  bool said_hello_ = false;
  bool frame_started_ = false;
  asio::steady_timer deadline_;
};

}  // namespace railcosim
