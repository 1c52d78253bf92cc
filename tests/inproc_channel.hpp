// A FramedChannel between two threads of one process: two queues of encoded
// frames, with the deadlines and the NetError kinds of the TCP one
// (connection.hpp). A master's RemoteParticipant talks over it to a
// NodeSession that a thread of the test serves (InprocNodes).
#pragma once

#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "connection.hpp"
#include "framed_channel.hpp"
#include "remote/remote_participant.hpp"
#include "session.hpp"
#include "wire.hpp"

namespace railcosim::test {

// What the two ends share: one queue of frames each way, and whether each
// end has closed.
struct InprocPipe {
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::string> frames[2];  // frames[k]: the frames end k reads
  bool closed[2] = {false, false};    // end k has closed
};

class InprocChannel final : public FramedChannel {
 public:
  InprocChannel(std::shared_ptr<InprocPipe> pipe, int end, std::string peer)
      : pipe_(std::move(pipe)), end_(end), peer_(std::move(peer)) {}
  ~InprocChannel() override { close(); }

  // Makes both ends of a new channel; `first` names the peer of the first
  // end (what its messages call the far end), `second` that of the second.
  static std::pair<std::unique_ptr<InprocChannel>, std::unique_ptr<InprocChannel>> pair(
      const std::string& first, const std::string& second) {
    auto pipe = std::make_shared<InprocPipe>();
    return {std::make_unique<InprocChannel>(pipe, 0, first),
            std::make_unique<InprocChannel>(pipe, 1, second)};
  }

  // The queue takes every frame at once (as a socket with room does): a
  // send fails only on a closed channel or a frame over the size limit.
  void send(const wire::Envelope& envelope, Duration /*timeout*/) override {
    std::string frame = encode_frame(envelope, kDefaultMaxFrameBytes);
    std::lock_guard<std::mutex> lock(pipe_->mutex);
    if (pipe_->closed[end_]) throw NetError(NetError::Kind::kClosed, "cannot send: closed");
    if (pipe_->closed[1 - end_])
      throw NetError(NetError::Kind::kClosed, "cannot send: the peer closed the channel");
    pipe_->frames[1 - end_].push_back(std::move(frame));
    pipe_->changed.notify_all();
  }

  wire::Envelope receive(Duration timeout) override {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + timeout;
    std::unique_lock<std::mutex> lock(pipe_->mutex);
    std::deque<std::string>& in = pipe_->frames[end_];
    while (in.empty()) {
      if (pipe_->closed[1 - end_] || pipe_->closed[end_])
        throw NetError(NetError::Kind::kClosed, "the peer closed the connection");
      if (const int sig = interrupt_signal())
        throw NetError(NetError::Kind::kInterrupted,
                       "interrupted by signal " + std::to_string(sig));
      if (Clock::now() >= deadline)
        throw NetError(NetError::Kind::kTimeout,
                       "no reply within " + std::to_string(timeout.count()) + " ms");
      // As the TCP channel does, look at the stop flag every kInterruptPoll.
      pipe_->changed.wait_until(lock, std::min(deadline, Clock::now() + kInterruptPoll));
    }
    const std::string frame = std::move(in.front());
    in.pop_front();
    lock.unlock();
    decoder_.feed(frame.data(), frame.size());
    wire::Envelope e;
    if (decoder_.next(e) != FrameDecoder::Status::kFrame)
      throw NetError(NetError::Kind::kProtocol, "the peer sent a frame that is not a message");
    return e;
  }

  std::string peer_name() const override { return peer_; }

  void close() override {
    std::lock_guard<std::mutex> lock(pipe_->mutex);
    pipe_->closed[end_] = true;
    pipe_->frames[end_].clear();
    pipe_->changed.notify_all();
  }

 private:
  std::shared_ptr<InprocPipe> pipe_;
  int end_;
  std::string peer_;
  FrameDecoder decoder_;
};

// Node sessions served by threads of this process, one per channel opened:
// what a node program does per connection, without a socket.
class InprocNodes {
 public:
  InprocNodes() = default;
  InprocNodes(const InprocNodes&) = delete;
  InprocNodes& operator=(const InprocNodes&) = delete;
  ~InprocNodes() {
    for (std::thread& t : threads_) t.join();
  }

  // Opens channels to sessions of a node serving `options`; the master's end
  // calls the node `peer`. With `offer_direct`, the sessions offer the direct
  // data plane (as a node program's do), which needs TCP.
  remote::ChannelOpener opener(NodeOptions options, std::string peer, bool offer_direct = false) {
    return [this, options = std::move(options), peer = std::move(peer),
            offer_direct](std::chrono::milliseconds) -> std::unique_ptr<FramedChannel> {
      auto [master_end, node_end] = InprocChannel::pair(peer, "master");
      threads_.emplace_back(serve, options, offer_direct, std::move(node_end));
      return std::move(master_end);
    };
  }

 private:
  // One session, request by request, until it ends or the master goes.
  static void serve(NodeOptions options, bool offer_direct,
                    std::unique_ptr<InprocChannel> channel) {
    NodeSession session(options);
    if (offer_direct) session.set_report_sink([](const std::string&) {});
    while (true) {
      wire::Envelope request;
      try {
        request = channel->receive(std::chrono::milliseconds(60000));
      } catch (const NetError&) {
        return;  // the master closed the channel (or fell silent)
      }
      bool close = false;
      const wire::Envelope reply = session.handle(request, close);
      try {
        channel->send(reply, std::chrono::milliseconds(10000));
      } catch (const NetError&) {
        return;
      }
      if (close) return;  // the channel's destructor closes it
    }
  }

  std::vector<std::thread> threads_;
};

}  // namespace railcosim::test
