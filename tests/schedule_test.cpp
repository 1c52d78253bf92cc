// The schedules' exchange order, checked with fake participants that record
// every call.
#include "schedule.hpp"

#include <gtest/gtest.h>

#include <functional>

namespace railcosim {
namespace {

// A participant built from lambdas: records calls in a shared log; its single
// output is `state + held input`, and a step adds 1 to its state.
class FakeParticipant final : public Participant {
 public:
  FakeParticipant(std::string name, std::vector<std::string>& log, double state)
      : name_(std::move(name)), log_(log), state_(state) {}
  std::string name() const override { return name_; }
  StepResult initialize() override {
    log_.push_back(name_ + ".initialize");
    return {outputs_now(), 0.0, true, std::nullopt};
  }
  void set_inputs(long n, const CouplingData& in) override {
    log_.push_back(name_ + ".set_inputs(" + std::to_string(n) + ", " + fmt(in.displacement[0]) +
                   ")");
    held_ = in.displacement[0];
  }
  CouplingData outputs() override {
    log_.push_back(name_ + ".outputs");
    return outputs_now();
  }
  void start_step(long n) override {
    log_.push_back(name_ + ".start_step(" + std::to_string(n) + ")");
    state_ += 1.0;
  }
  StepResult finish_step() override {
    log_.push_back(name_ + ".finish_step");
    return {outputs_now(), 0.0, true, std::nullopt};
  }
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {}; }
  void restore(const ParticipantState&) override {}

 private:
  static std::string fmt(double v) { return std::to_string(static_cast<int>(v)); }
  CouplingData outputs_now() const {
    CouplingData d;
    d.displacement = {state_ + held_};
    return d;
  }
  std::string name_;
  std::vector<std::string>& log_;
  double state_;
  double held_ = 0.0;
};

struct Fixture {
  std::vector<std::string> log;
  FakeParticipant s1{"s1", log, 100.0};
  FakeParticipant s2{"s2", log, 200.0};
};

TEST(JacobiSchedule, StartsBothStepsBeforeAwaitingEither) {
  Fixture f;
  JacobiSchedule j(f.s1, f.s2, Feedthrough::kLagged);
  j.initialize();
  f.log.clear();
  j.advance(0);
  // Both take the other's outputs at t_n (s1: 100, s2: 200).
  const std::vector<std::string> expected = {"s1.set_inputs(0, 200)", "s2.set_inputs(0, 100)",
                                             "s1.start_step(0)",      "s2.start_step(0)",
                                             "s1.finish_step",        "s2.finish_step"};
  EXPECT_EQ(f.log, expected);
  f.log.clear();
  j.advance(1);
  // Outputs at the end of step 0: s1 = 101 + 200 held, s2 = 201 + 100 held.
  EXPECT_EQ(f.log[0], "s1.set_inputs(1, 301)");
  EXPECT_EQ(f.log[1], "s2.set_inputs(1, 301)");
}

TEST(JacobiSchedule, ResolvedReadsS1AfterItReceivedTheFreshInput) {
  Fixture f;
  JacobiSchedule j(f.s1, f.s2, Feedthrough::kResolved);
  j.initialize();
  f.log.clear();
  j.advance(0);
  // s1 first holds s2's 200, then its output is read: 100 + 200 = 300.
  const std::vector<std::string> expected = {
      "s1.set_inputs(0, 200)", "s1.outputs",     "s2.set_inputs(0, 300)", "s1.start_step(0)",
      "s2.start_step(0)",      "s1.finish_step", "s2.finish_step"};
  EXPECT_EQ(f.log, expected);
}

TEST(GaussSeidelSchedule, S2StepsWithS1sNewOutputs) {
  Fixture f;
  GaussSeidelSchedule gs(f.s1, f.s2);
  gs.initialize();
  f.log.clear();
  gs.advance(0);
  // s1 steps with s2's 200 to 101; s2 then gets 101 + 200 = 301.
  const std::vector<std::string> expected = {"s1.set_inputs(0, 200)", "s1.start_step(0)",
                                             "s1.finish_step",        "s2.set_inputs(0, 301)",
                                             "s2.start_step(0)",      "s2.finish_step"};
  EXPECT_EQ(f.log, expected);
}

TEST(MakeSchedule, ResolvedFeedthroughOnlyUnderJacobi) {
  Fixture f;
  EXPECT_THROW(make_schedule(Scheme::kGaussSeidel, Feedthrough::kResolved, f.s1, f.s2),
               std::invalid_argument);
  EXPECT_NE(dynamic_cast<JacobiSchedule*>(
                make_schedule(Scheme::kJacobi, Feedthrough::kResolved, f.s1, f.s2).get()),
            nullptr);
  EXPECT_NE(dynamic_cast<GaussSeidelSchedule*>(
                make_schedule(Scheme::kGaussSeidel, Feedthrough::kLagged, f.s1, f.s2).get()),
            nullptr);
}

}  // namespace
}  // namespace railcosim
