// A framed TCP connection with deadlines (the FramedChannel over TCP), used
// by the master to talk to a node (and by tests to talk to a node like any
// other client would). Asio
// connects; reads and writes are blocking recv()/send() calls on the socket
// with a timeout of one kInterruptPoll, so that a message costs one system
// call each way when the peer is ready (no read that must fail first).
#pragma once

#include <utility>  // before Asio: its headers use std::exchange

#include <array>
#include <atomic>
#include <boost/asio.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "framed_channel.hpp"
#include "wire.hpp"

namespace railcosim {

struct Address {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string str() const { return host + ":" + std::to_string(port); }
};

// Parses "HOST:PORT" (or ":PORT", or "[v6]:PORT"); throws std::invalid_argument
// naming `what` (e.g. "--listen").
Address parse_address(const std::string& text, const std::string& what);

// A process-wide stop flag (a signal number once set, e.g. by a SIGINT
// handler). Every wait of every Connection looks at it at least every
// kInterruptPoll and gives up with NetError(kInterrupted) once it is set, so
// a master blocked on a silent or dripping node still stops within a second.
void set_interrupt_flag(const std::atomic<int>* flag);
// The signal that asks to stop, or 0 (for waits outside a Connection).
int interrupt_signal();
inline constexpr std::chrono::milliseconds kInterruptPoll{100};

class Connection final : public FramedChannel {
 public:
  // Connects, retrying with back-off until `timeout` has passed (a node may
  // still be starting). Throws NetError(kConnect) naming the address.
  static std::unique_ptr<Connection> connect(const Address& address, Duration timeout);

  ~Connection() override;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // Every timeout bounds a whole message: a peer that sends a reply one byte
  // at a time does not restart it.
  // Writes one frame. Throws NetError on failure or after `timeout`.
  void send(const wire::Envelope& envelope, Duration timeout = Duration(10000)) override;
  // Writes raw bytes (tests use it to send malformed frames).
  void send_raw(const std::string& bytes, Duration timeout = Duration(10000));
  // Reads one frame. Throws NetError if none arrives within `timeout`.
  wire::Envelope receive(Duration timeout) override;

  const Address& peer() const { return peer_; }
  std::string peer_name() const override { return peer_.str(); }
  Connection* tcp() override { return this; }

  // For a caller that waits on several connections at once (poll on fd()):
  int fd() { return socket_.native_handle(); }
  // A frame already read and buffered, if any. Throws NetError(kProtocol).
  bool next_buffered(wire::Envelope& out);
  // Bytes of a frame begun but not yet whole.
  std::size_t partial_bytes() const { return decoder_.buffered(); }
  // One read of what the socket holds now, without waiting; false when the
  // peer has closed the connection. Throws NetError(kIo).
  bool read_now();
  // Hands the socket over as a plain descriptor (this connection is closed
  // without shutting the TCP connection down). -1 if it is not open.
  int release_fd();

  // Stops sending (the peer sees end of stream) but keeps reading.
  void shutdown_send();
  void close() override;

 private:
  explicit Connection(Address peer);
  // Makes the socket blocking, with send and receive timeouts of one
  // kInterruptPoll: reads and writes are then plain send()/recv() calls.
  void use_blocking_io();
  // Throws NetError(kInterrupted) when the stop flag is set, and
  // NetError(kTimeout, "no WHAT within TIMEOUT ms") past `deadline`.
  void check_wait(std::chrono::steady_clock::time_point deadline, Duration timeout,
                  const char* what) const;

  Address peer_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::socket socket_;
  std::size_t max_frame_ = kDefaultMaxFrameBytes;
  FrameDecoder decoder_;
  std::array<char, 65536> buffer_{};
};

}  // namespace railcosim
