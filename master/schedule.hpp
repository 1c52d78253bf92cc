// Co-simulation schedules: the order in which two participants exchange
// values and step over one macro step [nH, (n+1)H]. Jacobi and Gauss–Seidel
// are siblings behind one interface; the master's loop knows neither.
#pragma once

#include <memory>

#include "cosim_case.hpp"
#include "participant.hpp"

namespace railcosim {

// The outcome of one macro step for both sides.
struct MacroStepResult {
  StepResult s1, s2;
};

class Schedule {
 public:
  // s1 holds the wheel, s2 the sleepers. Both must outlive the schedule.
  Schedule(Participant& s1, Participant& s2) : s1_(s1), s2_(s2) {}
  virtual ~Schedule() = default;

  // Initialises both participants and keeps their outputs at t = 0.
  MacroStepResult initialize();
  // Exchanges and steps from nH to (n+1)H.
  virtual MacroStepResult advance(long n) = 0;

 protected:
  Participant& s1_;
  Participant& s2_;
  CouplingData out1_, out2_;  // the latest outputs of each side
};

// Parallel: both sides take their inputs from the other's outputs at t_n and
// step at the same time (both steps are started before either is awaited).
// Lagged: S1's force output is the one it computed at the end of its last
// step. Resolved: S1 first receives S2's fresh displacement, then its force is
// read, so S2 gets F(q(t_n), w(t_n)).
class JacobiSchedule final : public Schedule {
 public:
  JacobiSchedule(Participant& s1, Participant& s2, Feedthrough feedthrough)
      : Schedule(s1, s2), feedthrough_(feedthrough) {}
  MacroStepResult advance(long n) override;

 private:
  Feedthrough feedthrough_;
};

// Sequential: S1 steps with S2's outputs at t_n; S2 then steps with S1's
// outputs at t_n + H.
class GaussSeidelSchedule final : public Schedule {
 public:
  using Schedule::Schedule;
  MacroStepResult advance(long n) override;
};

// Throws std::invalid_argument for a combination that does not exist
// (resolved feedthrough under Gauss–Seidel).
std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough, Participant& s1,
                                        Participant& s2);

}  // namespace railcosim
