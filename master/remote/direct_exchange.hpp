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

// Why a run stays relayed: the nodes that lack what its coupling needs on
// the direct plane ("lockstep" for the couplings the master decides step by
// step, "direct" for windows), by name and address; "" when none lacks it.
std::string relay_reason(const std::vector<Participant*>& participants, bool lockstep);

// What the master knows of one node when a macro step is held up: who
// holds it up is judged from these alone (direct_blame.cpp).
struct HoldUp {
  std::string role;
  std::vector<std::string> peers;  // the participants it has a peer link with
  long reported = 0;               // its last step report
  bool has_step = false;           // it has reported the macro step waited for
  std::string waiting_for;         // the participant it says it waits for ("" none)
  std::chrono::steady_clock::time_point claimed_at{};  // when it said so
  // Its last frame that moved the run on: a step report, a window's reply,
  // a progress frame that counted.
  std::chrono::steady_clock::time_point last_useful{};
};

// Who holds the step up, and what the master knows of the claims, for the
// failure's message. A claim to wait for a peer it has no link with (or for
// no participant of the run) is false: the claimant. Otherwise a claim is
// believed, whatever the peer's step reports say (a node's reports are not
// the data it sends its peers: a node may report steps and withhold its
// data): the participant that others wait for and that waits for nobody,
// following claims to their end; where claims go round, the one whose step
// reports went furthest (it passed the point its claimant waits at), or on a
// tie the one named by the earliest claim. With no claim, of the nodes that
// have not reported the step, the one that reported least, then the one
// silent longest.
struct Blamed {
  std::size_t node = 0;
  std::string claim;  // "; it says it waits for ..." when its own claim is refuted
};
Blamed blame(const std::vector<HoldUp>& nodes);

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
  // Throws NodeFailure, once the run has reached its end, for a node whose
  // window broke the rules on the way (its reports or its end).
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
    std::chrono::steady_clock::time_point claimed_at{};
    std::vector<std::string> peers;  // its links' peers
    // Its last frame that moved the run on (a step report, a window's reply,
    // a progress frame that counted): a node's deadline counts from it, so
    // one node's frames do not extend another's.
    std::chrono::steady_clock::time_point last_useful{};
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
  // When the nodes that have not reported the step waited for last moved
  // the run on (Node::last_useful): the deadline counts from it, so bytes
  // that trickle in, empty report frames, and the frames of a node that has
  // reported the step do not extend it.
  std::chrono::steady_clock::time_point last_useful() const;
  long step_ = 0;         // the macro step being waited for, for messages
  long window_end_ = -1;  // of the window granted last (-1: none yet)
  // After every node has ended its window: names the node that cannot give
  // macro step n (its reports stop short, or it stopped early) unless all
  // ended where the window ends.
  void check_window_end(long n);
  std::chrono::steady_clock::time_point first_peer_failure_{};
};

}  // namespace railcosim::remote
