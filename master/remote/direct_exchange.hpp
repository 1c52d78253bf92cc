// The master's side of the direct data plane. The nodes send each other their
// coupling data over peer links; the master hands out the links, grants
// windows of macro steps, and takes the step reports the nodes stream to it,
// one macro step at a time, exactly as a schedule's advance() returns them:
// the run's loop (divergence, history, progress) is the same on both planes.
//
// Used for explicit coupling with held inputs when every participant is a
// remote node that offers it. The couplings the master decides step by step
// (implicit iterations, ramped inputs) run on the direct plane in lock step
// instead (enter_lockstep): the master's executor sends each node one frame
// per step or iteration, which the node serves without its event loop.
#pragma once

#include <chrono>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "cosim_case.hpp"
#include "engine/step_executor.hpp"
#include "engine/step_plan.hpp"
#include "model.hpp"
#include "participant.hpp"
#include "remote/data_plane.hpp"
#include "remote/remote_participant.hpp"

namespace railcosim::remote {

// Puts every participant into lock step for macro steps [first, end) and
// returns true, if every one is a RemoteParticipant whose node offers it;
// false (nothing sent) otherwise.
bool enter_lockstep(const std::vector<Participant*>& participants, long first, long end);

class DirectExchange final : public engine::MacroSteps {
 public:
  // nullptr unless every participant is a RemoteParticipant whose node offers
  // the direct data plane; throws NodeFailure naming a participant that
  // offers it over another channel than TCP. Otherwise sends every node its links, which say
  // what the step plan says (the schedule's plan, compiled at initialize()):
  // which peer's data it waits for at n + 1, which peer sends twice.
  // `bound`: the divergence bound (m).
  static std::unique_ptr<DirectExchange> make(const std::vector<Participant*>& participants,
                                              const engine::StepPlan& plan, double bound,
                                              long total_steps, DirectOptions options = {});

  // The results of macro step n, from the nodes' reports (granting the next
  // window when the last one has ended). Throws StepFailure for a node whose
  // step failed and NodeFailure for one that closed, broke or fell silent.
  std::vector<StepResult> advance(long n) override;
  // Closes the connections of nodes still in a window: their sessions cannot
  // take requests any more (they end their windows when they notice).
  ~DirectExchange();
  // Waits (a few seconds at most) for every window in progress to end, so
  // the sessions take requests again (final results after a divergence).
  void drain();

 private:
  struct Node {
    RemoteParticipant* p = nullptr;
    std::deque<StepResult> reports;
    long reported = 0;  // the last point reported
    bool in_window = false;
    long done_step = -1;  // where its last window ended
    std::string done_reason;
    bool closed = false;  // its connection is gone
    // A failure that ends the run once the master reaches its step.
    bool failed = false;
    bool step_failure = false;
    bool peer_failed = false;  // it lost a peer: the root cause is elsewhere
    int sender = -1;           // the node whose data it rejected, if any
    std::string waiting_for;   // the peer it said it waits for
    std::chrono::steady_clock::time_point last_frame{};
    long idle_frames = 0;  // report frames without a step report since its last one
    // Its progress frames in the window: the last counted (a later step, or
    // the same step and more micro steps); since its last step report, those
    // counted and those that were not.
    long progress_step = -1;
    std::uint64_t progress_micro = 0;
    long counted_progress = 0;
    long stale_progress = 0;
    long fail_step = 0;
    std::string fail_text;
  };
  DirectExchange(std::vector<RemoteParticipant*> nodes, double bound, long total,
                 DirectOptions options);
  void grant(long n);
  // Waits up to `timeout` for frames from the nodes in a window and takes
  // them; false when none came. Throws std::runtime_error once the stop
  // flag (interrupt_signal()) is set: it looks every kInterruptPoll.
  bool read(std::chrono::milliseconds timeout);
  void take(Node& node, const wire::Envelope& e);
  // Names the node that holds macro step n up: silent for `waited`, or
  // (budget) still at it when the step's budget ran out.
  [[noreturn]] void silence(long n, std::chrono::milliseconds waited, bool budget = false);
  // A progress frame: moves the deadline on when it counts.
  void take_progress(Node& node, const wire::Envelope& e);
  // The participant a node says it waits for (nullptr: none, or not one of
  // this run's), and the first node whose claim what the master knows
  // refutes: the peer it names reported past the claimant's point.
  const Node* claimed(const Node& claimant) const;
  Node* false_claimant();
  // The failure that ends macro step n (or, with any_step, any failure),
  // ranked by root cause: a failed step or data rejected (blamed on its
  // sender), then a node that closed its connection, then the others, then
  // nodes that only lost a peer; in load order within a rank. nullptr if
  // none is due yet (a failed node's reports not all taken).
  const Node* culprit(long n, bool any_step) const;
  // Throws the culprit's failure. A node that only lost a peer is given a
  // moment for the peer's own failure to arrive, which names the cause.
  void fail_with(const Node& node);

  std::vector<Node> nodes_;
  double bound_;
  long total_;
  DirectOptions options_;
  // How long a node may stay silent: step_factor times the longest time per
  // step seen (the gap between two report frames of one node over the steps
  // in the second), within [step_min, step_max] (RemoteTimeouts, as for a
  // relayed step); step_max before any is measured.
  std::chrono::milliseconds progress() const;
  std::chrono::steady_clock::duration slowest_gap_{0};
  // The last frame that moved the run on (a step report or a window's
  // reply): the deadline counts from it, so bytes that trickle in or empty
  // report frames do not extend it.
  std::chrono::steady_clock::time_point last_useful_{};
  long step_ = 0;         // the macro step being waited for, for messages
  long window_end_ = -1;  // of the window granted last (-1: none yet)
  // After every node has ended its window: names the node that cannot give
  // macro step n (its reports stop short, or it stopped early) unless all
  // ended where the window ends.
  void check_window_end(long n);
  std::chrono::steady_clock::time_point first_peer_failure_{};
};

}  // namespace railcosim::remote
