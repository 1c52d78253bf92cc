// A connection's next request, read on the calling thread: the master's
// requests during a lock step (session_lockstep.cpp), which the node serves
// without its event loop. Frames the connection has buffered already come
// first; then the socket is read with poll and recv, one recv per frame
// when it arrives whole.
#pragma once

#include <atomic>
#include <chrono>
#include <vector>

#include "wire.hpp"

namespace railcosim {

struct FrameSourceLimits {
  // Between requests the master may stay silent this long.
  std::chrono::milliseconds idle{60000};
  // A request, once begun, must arrive whole this fast.
  std::chrono::milliseconds message{10000};
};

class FrameSource {
 public:
  // `decoder`: the connection's own (it may hold the start of the next
  // frame). `stop`: set when the node shuts down (looked at every 100 ms).
  FrameSource(int fd, FrameDecoder& decoder, FrameSourceLimits limits,
              const std::atomic<bool>* stop)
      : fd_(fd), decoder_(decoder), limits_(limits), stop_(stop) {}

  // The next request; false when the master closed the connection between
  // frames. Throws ProtocolError: TIMEOUT (silent too long), BAD_FRAME or
  // FRAME_TOO_LARGE (the stream is lost), INTERNAL (the node shuts down,
  // or the connection broke in the middle of a frame).
  bool next(wire::Envelope& out);
  // Blocking reads with a receive timeout of 100 ms (one system call per
  // frame), for as long as nothing else uses the socket; off again before
  // the event loop takes it back.
  void set_blocking(bool on);
  // Whether the master has closed or broken the connection (does not wait).
  bool hung_up() const;

 private:
  int fd_;
  FrameDecoder& decoder_;
  FrameSourceLimits limits_;
  const std::atomic<bool>* stop_;
  std::vector<char> buf_ = std::vector<char>(65536);
  bool blocking_ = false;
};

}  // namespace railcosim
