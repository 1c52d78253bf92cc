// A participant's own part of the schedule on the direct data plane: it runs
// a window of macro steps, taking its inputs from the peers' data and sending
// them its outputs at every communication point, in the order the master's
// Jacobi or Gauss–Seidel schedule would (the results are bitwise the same),
// and streams its step reports to the master.
//
// Per macro step n, on every link: receive the peer's outputs at point n (at
// n + 1 when the peer steps first under Gauss–Seidel), set the inputs, step,
// send the outputs at n + 1. Under Jacobi with resolved feedthrough a
// participant that sends forces sends its outputs again once it has the
// step's inputs, and its peers set their inputs again from them.
//
// Stopping: a participant whose step diverges (its largest |u| over the
// window's bound, or a value not finite) marks its data at that point as the
// last; one that fails a step or is told to stop sends a marker with no data.
// A participant stops when it reaches the point a peer said it stops at.
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fd_channel.hpp"
#include "peer_links.hpp"
#include "subsystem.hpp"
#include "wire.hpp"

namespace railcosim {

// The counts a participant's inputs have, per interface: displacements,
// velocities, forces (one per coupling point of a quantity it receives, none
// of the others), as the configure gives them: the coupling points of each
// interface (for a built-in participant, checked against its scene when it
// is built).
using InputShape = std::vector<std::array<std::size_t, 3>>;
InputShape input_shape(const wire::Configure& c);

class WindowRunner {
 public:
  // `outputs`: the participant's outputs at communication point `point` (its
  // initialize() result before the first window). Report frames stay within
  // `max_frame_bytes` (the node's --max-frame-bytes): a block of reports is
  // split over as many frames as it needs.
  // `shape`: the counts of the participant's inputs per interface, from the
  // scene, against which every peer's data is checked.
  WindowRunner(Participant& participant, LinksPlan plan,
               std::vector<std::unique_ptr<FdChannel>> links, double macro_step,
               CouplingData outputs, InputShape shape, long point,
               std::size_t max_frame_bytes = kDefaultMaxFrameBytes);

  // Runs steps from the current point to w.end_step(). `report` sends one
  // encoded frame to the master. Returns where it stopped and why; throws
  // StepFailure (the step's integrator gave up: the peers and the reports
  // already know) or LinkError (a link broke: the peers are told to stop).
  // `abandoned` is asked while a peer's data keeps it waiting: true when
  // the master has gone (the window then ends).
  wire::WindowDone run(const wire::Window& w, std::uint64_t id,
                       const std::function<void(const std::string&)>& report,
                       const std::function<bool()>& abandoned = {});
  long point() const { return point_; }

 private:
  struct Link {
    std::unique_ptr<FdChannel> channel;
    LinkPlan plan;
    long have = -1;  // the point of `data` (one before the first point: none yet)
    CouplingData data;
    long fresh_have = -1;  // resolved feedthrough: the second sending
    CouplingData fresh;
  };
  // Sends the outputs at the current point on every link.
  void send_outputs(const CouplingData& outputs, bool last, bool refresh);
  void send_stop();
  // Reads link `l` until it holds the peer's data at `need`; false if the
  // peer stops before that point.
  bool await(Link& l, long need, bool fresh);
  // Checks one PeerData from link `l` against what is due (its point, its
  // shape, finite values) and keeps it; throws LinkError naming the sender.
  void take(Link& l, const wire::PeerData& d);
  // " at macro step N (t = ... s)", for errors.
  std::string at() const;
  CouplingData inputs(bool fresh) const;
  // Sets the inputs of macro step n from the peers' data; data the
  // participant rejects is a LinkError naming the peer that sent it.
  void set_inputs(long n, bool fresh);
  void flush(std::uint64_t id, const std::function<void(const std::string&)>& report,
             const std::string& waiting_for = "");

  Participant& sub_;
  std::size_t max_frame_bytes_;
  std::vector<Link> links_;
  bool refresh_;
  std::chrono::milliseconds timeout_;
  double macro_step_;
  CouplingData outputs_;
  InputShape shape_;
  long point_;
  long sent_ = -1;  // the last point whose data went out
  bool sent_last_ = false;
  long end_ = 0;     // where this participant stops
  std::string why_;  // why it stops before the window's end
  wire::Reports pending_;
  std::uint64_t id_ = 0;  // of the window being run
  const std::function<void(const std::string&)>* report_ = nullptr;
  const std::function<bool()>* abandoned_ = nullptr;
};

}  // namespace railcosim
