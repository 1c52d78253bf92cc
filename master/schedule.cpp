#include "schedule.hpp"

#include <stdexcept>

namespace railcosim {

MacroStepResult Schedule::initialize() {
  MacroStepResult r{s1_.initialize(), s2_.initialize()};
  out1_ = r.s1.outputs;
  out2_ = r.s2.outputs;
  return r;
}

MacroStepResult JacobiSchedule::advance(long n) {
  s1_.set_inputs(n, out2_);
  if (feedthrough_ == Feedthrough::kResolved) out1_ = s1_.outputs();
  s2_.set_inputs(n, out1_);
  s1_.start_step(n);
  s2_.start_step(n);
  MacroStepResult r{s1_.finish_step(), s2_.finish_step()};
  out1_ = r.s1.outputs;
  out2_ = r.s2.outputs;
  return r;
}

MacroStepResult GaussSeidelSchedule::advance(long n) {
  s1_.set_inputs(n, out2_);
  MacroStepResult r;
  r.s1 = s1_.step(n);
  out1_ = r.s1.outputs;
  s2_.set_inputs(n, out1_);
  r.s2 = s2_.step(n);
  out2_ = r.s2.outputs;
  return r;
}

std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough, Participant& s1,
                                        Participant& s2) {
  if (scheme == Scheme::kJacobi) return std::make_unique<JacobiSchedule>(s1, s2, feedthrough);
  if (feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved exists only for Jacobi schedules: under Gauss–Seidel, S1's "
        "force at the end of its step necessarily uses the input it held");
  return std::make_unique<GaussSeidelSchedule>(s1, s2);
}

}  // namespace railcosim
