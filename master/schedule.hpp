// Co-simulation schedules: the order in which the participants exchange
// values and step over one macro step [nH, (n+1)H]. Jacobi and Gauss–Seidel
// are siblings behind one interface; the master's loop knows neither, and
// neither knows how many participants there are or what they hold.
#pragma once

#include <memory>
#include <vector>

#include "cosim_case.hpp"
#include "model.hpp"
#include "participant.hpp"

namespace railcosim {

// Where one input comes from: participant and interface index of the sender.
struct Route {
  int participant = -1;
  int interface = -1;
};
// For participant p and its interface j, routing[p][j] names the sender.
using Routing = std::vector<std::vector<Route>>;

// The routing of a partition: each interface receives what its peer's
// interface on the same cut sends.
Routing make_routing(const std::vector<ParticipantSpec>& participants);

// Whether these outputs carry a force on any interface (such a sender is
// read again under Jacobi with resolved feedthrough).
bool sends_force(const CouplingData& outputs);

class Schedule {
 public:
  // The participants in load order; they must outlive the schedule.
  Schedule(std::vector<Participant*> participants, Routing routing)
      : ps_(std::move(participants)), routing_(std::move(routing)) {}
  virtual ~Schedule() = default;

  // Initialises every participant with its inputs at t = 0 (the coupled
  // static state) and keeps their outputs.
  std::vector<StepResult> initialize(const std::vector<CouplingData>& inputs);
  // Exchanges and steps from nH to (n+1)H.
  virtual std::vector<StepResult> advance(long n) = 0;

 protected:
  // Participant p's inputs, from the latest outputs of its senders.
  CouplingData inputs_for(std::size_t p) const;
  void keep_outputs(const std::vector<StepResult>& r);

  std::vector<Participant*> ps_;
  Routing routing_;
  std::vector<CouplingData> out_;  // the latest outputs of each participant
};

// Parallel: every participant takes its inputs from the others' outputs at
// t_n and they step at the same time (every step is started before any is
// awaited). Lagged: a force output is the one computed at the end of the
// sender's last step. Resolved: the senders of forces first receive their
// fresh displacements, then their forces are read, so the receivers get
// F(state at t_n, inputs at t_n).
class JacobiSchedule final : public Schedule {
 public:
  JacobiSchedule(std::vector<Participant*> participants, Routing routing, Feedthrough feedthrough)
      : Schedule(std::move(participants), std::move(routing)), feedthrough_(feedthrough) {}
  std::vector<StepResult> advance(long n) override;

 private:
  Feedthrough feedthrough_;
};

// Sequential, in load order: each participant steps with the freshest
// outputs of those before it (at t_n + H) and of those after it (at t_n).
class GaussSeidelSchedule final : public Schedule {
 public:
  using Schedule::Schedule;
  std::vector<StepResult> advance(long n) override;
};

// Throws std::invalid_argument for a combination that does not exist
// (resolved feedthrough under Gauss–Seidel).
std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        std::vector<Participant*> participants, Routing routing);

}  // namespace railcosim
