// A participant that lives in a node process: the master's proxy for it.
// Every call becomes a message to the node; the schedules cannot tell it
// from an in-process Subsystem.
#pragma once

#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <optional>

#include "connection.hpp"
#include "framed_channel.hpp"
#include "participant.hpp"
#include "remote/reply_check.hpp"
#include "remote/step_watch.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim::remote {

// How long the master waits for a node. A step's deadline follows from the
// cost of the steps seen so far: step_factor times the slowest one, within
// [step_min, step_max]; before the first step is timed, step_max applies.
// The same rule on both data planes (a relayed step's reply; on the direct
// plane the time between a node's step reports); step_min is the floor a
// user raises (--step-deadline-floor, [coupling] step_deadline_floor).
struct RemoteTimeouts {
  std::chrono::milliseconds connect{10000};  // with retries: a node may still be starting
  // A node that answers the hello with BUSY (another session holds it, or
  // eight other connections are in their hello, each for at most 10 s) is
  // asked again for this long.
  std::chrono::milliseconds busy{20000};
  std::chrono::milliseconds reply{10000};  // hello, configure and every other request
  std::chrono::milliseconds step_min{2000};
  std::chrono::milliseconds step_max{30000};
  double step_factor = 50.0;
  // The most a macro step may take, however much progress the node shows
  // (--step-budget, [coupling] step_budget).
  std::chrono::milliseconds step_budget{kDefaultStepBudget};
  // Nodes send progress frames at most this often (Configure.progress_ms).
  std::chrono::milliseconds progress{100};
  static constexpr std::chrono::milliseconds kDefaultStepBudget{120000};
  // A Statics request must show progress within `reply` and end within
  // this many step budgets, however much progress it shows.
  static constexpr int kStaticsBudgetSteps = 10;
  std::chrono::milliseconds statics_budget() const { return step_budget * kStaticsBudgetSteps; }
};

// A failure of a remote node, with its name, address, macro step and time.
class NodeFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Opens a new channel to the node within the connect timeout (called again
// while the node answers BUSY). Throws NetError(kConnect).
using ChannelOpener = std::function<std::unique_ptr<FramedChannel>(std::chrono::milliseconds)>;

class RemoteParticipant final : public Participant {
 public:
  // Connects over TCP, says hello (checking the node's role and the scene)
  // and configures the node's subsystem. Throws NodeFailure.
  // `token`: the shared secret, for nodes started with --token-file.
  RemoteParticipant(const Address& address, const Scene& scene, const SubsystemConfig& config,
                    RemoteTimeouts timeouts = {}, std::optional<std::string> token = std::nullopt);
  // The same over the channels `open` makes; `peer` names the node's end in
  // messages (where the TCP form gives its address).
  RemoteParticipant(ChannelOpener open, std::string peer, const Scene& scene,
                    const SubsystemConfig& config, RemoteTimeouts timeouts = {},
                    std::optional<std::string> token = std::nullopt);
  ~RemoteParticipant() override;

  std::string name() const override;
  Channels channels() const override { return channels_; }
  CouplingData statics(const CouplingData& inputs) override;
  StepResult initialize(const CouplingData& inputs) override;
  void set_inputs(long n, const CouplingData& inputs) override;
  void set_inputs(long n, const CouplingData& start, const CouplingData& end) override;
  // Substep waveforms (remote_waveforms.cpp): relayed data plane only.
  void set_input_waveforms(long n, const InputWaveforms& inputs) override;
  void record_samples(bool on) override;
  OutputSamples step_samples() const override { return samples_; }
  CouplingData outputs() override;
  void start_step(long n) override;
  StepResult finish_step() override;
  ParticipantResults results() override;
  ParticipantState save() override;
  void restore(const ParticipantState& state) override;

  // The direct data plane (direct_exchange.hpp) drives these.
  bool direct_capable() const { return direct_; }
  // Lock step (the direct plane's form for couplings the master decides
  // step by step): the node serves the step requests without its event
  // loop and keeps its checkpoints itself (save() returns a kept state).
  bool lockstep_capable() const { return lockstep_capable_; }
  void enter_lockstep(long first_step, long end_step);
  const Address& address() const { return address_; }
  const std::string& role() const { return config_.participant.role; }
  double macro_step() const { return config_.macro_step; }
  const RemoteTimeouts& timeouts() const { return timeouts_; }
  // The TCP connection to the node, or nullptr over another channel (the
  // direct data plane polls sockets: it needs TCP).
  Connection* tcp() { return conn_ ? conn_->tcp() : nullptr; }
  // Sends the links and waits for the node's ack.
  void set_links(const wire::Links& links);
  // Sends a window; its reports and its reply are read through tcp().
  void grant(const wire::Window& window);
  // A Reports frame of the window: its id must be the window's.
  void accept_reports_frame(std::uint64_t id) const;
  // One report of the window, checked as a step's reply is (and not past
  // the window's end).
  StepResult accept_report(const wire::StepReport& report);
  // The window's reply: true when it is the WindowDone of the window granted;
  // an error reply becomes StepFailure or NodeFailure as a step's would.
  void window_reply(const wire::Envelope& reply);
  // Fails with `what` at macro step `step`.
  [[noreturn]] void fail_at(long step, const std::string& what);
  // The text of that failure: "NAME at ADDR: WHAT at macro step N (t = T s)",
  // or "... WHAT before the run" before the first step's inputs.
  std::string failure_text(long step, const std::string& what) const;

 private:
  // Sends a request; replies are read later, in order.
  void send(wire::Envelope request, bool expects_ack);
  // Reads replies until the one for the latest non-ack request; acks of
  // pipelined requests are consumed on the way.
  // `watch`: a step's reply, whose progress frames it takes and whose
  // deadlines it keeps (instead of `timeout`).
  wire::Envelope await(wire::Envelope::BodyCase expected, const char* what,
                       std::chrono::milliseconds timeout, StepWatch* watch = nullptr);
  wire::Envelope await(wire::Envelope::BodyCase expected, const char* what) {
    return await(expected, what, timeouts_.reply);
  }
  std::chrono::milliseconds step_deadline() const;
  [[noreturn]] void fail(const std::string& what) const;
  // Fails with `why` unless it is empty (see reply_check.hpp).
  void check(const std::string& why) const {
    if (!why.empty()) fail("bad reply: " + why);
  }
  // Flushes held inputs, sends `e`, returns its reply of the expected kind.
  wire::Envelope request(wire::Envelope e, wire::Envelope::BodyCase expected);
  // Sends inputs held back by set_inputs() as a message of their own.
  void flush_inputs();
  // Moves the pending inputs into a Step or SetInputs (false: none pending).
  template <class Message>
  bool take_pending(Message* m);
  // Keeps a step report's samples (recording on), checked.
  void keep_samples(const wire::StepReport& report);

  // Connects and says hello, again while the node answers BUSY; returns its
  // reply to the hello. Throws NodeFailure.
  wire::Envelope open_session(const Scene& scene, const std::string& nonce);
  // Says hello, authenticates and configures (both constructors).
  void start(const Scene& scene, const std::optional<std::string>& token);

  ChannelOpener open_;
  std::string peer_;  // for messages
  Address address_;   // over TCP: for the peer links of the direct plane
  SubsystemConfig config_;
  RemoteTimeouts timeouts_;
  std::unique_ptr<FramedChannel> conn_;
  std::uint64_t next_id_ = 1;
  int pending_acks_ = 0;
  long step_ = 0;          // the macro step being done, for messages
  long window_end_ = 0;    // the end of the window granted (direct plane)
  bool stepping_ = false;  // inputs for a step or a window were given: the run has begun
  std::chrono::steady_clock::time_point step_started_;
  std::chrono::steady_clock::duration slowest_step_{0};
  // set_inputs() keeps its data here; the next step carries it.
  std::optional<CouplingData> pending_inputs_;
  std::optional<CouplingData> pending_end_;      // inputs that ramp: their value at the step's end
  std::optional<InputWaveforms> pending_waves_;  // or the inputs as waveforms
  bool record_ = false;                          // step reports carry samples
  OutputSamples samples_;                        // those of the last step
  Channels channels_;                            // as the node declared them
  ReplyShape shape_;                             // what its replies must look like
  std::deque<std::uint64_t> in_flight_;          // ids of the requests not answered yet
  bool direct_ = false;                          // the node offers the direct data plane
  bool lockstep_capable_ = false;                // ... and the lock step
  bool lockstep_ = false;                        // in lock step
  // Lock step: a checkpoint to keep, or to restore, before the next step.
  bool pending_keep_ = false;
  bool pending_restore_ = false;
};

}  // namespace railcosim::remote
