// The schedules' exchange order, checked with fake participants that record
// every call.
#include "engine/schedule.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "scene.hpp"

namespace railcosim {
namespace {

using engine::GaussSeidelSchedule;
using engine::JacobiSchedule;
using engine::make_routing;
using engine::make_schedule;
using engine::Routing;
using engine::sends_force;

// A participant that records calls in a shared log. It has `interfaces`
// interfaces; the output on each is `state + the input held there`, sent as
// a force if `sends_force`, else as a displacement; a step adds 1 to its
// state.
class FakeParticipant final : public Participant {
 public:
  FakeParticipant(std::string name, std::vector<std::string>& log, double state, int interfaces,
                  bool sends_force = false)
      : name_(std::move(name)),
        log_(log),
        state_(state),
        held_(static_cast<std::size_t>(interfaces), 0.0),
        force_(sends_force) {}
  std::string name() const override { return name_; }
  Channels channels() const override { return {}; }
  CouplingData statics(const CouplingData&) override { return outputs_now(); }
  StepResult initialize(const CouplingData& in) override {
    log_.push_back(name_ + ".initialize");
    hold(in);
    return {outputs_now(), 0.0, true, {}};
  }
  void set_inputs(long n, const CouplingData& in) override {
    hold(in);
    std::string values;
    for (double h : held_) values += ", " + std::to_string(static_cast<int>(h));
    log_.push_back(name_ + ".set_inputs(" + std::to_string(n) + values + ")");
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
    return {outputs_now(), 0.0, true, {}};
  }
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {}; }
  void restore(const ParticipantState&) override {}

 private:
  void hold(const CouplingData& in) {
    for (std::size_t j = 0; j < in.size() && j < held_.size(); ++j)
      held_[j] = in[j].force.empty() ? in[j].displacement.at(0) : in[j].force.at(0);
  }
  CouplingData outputs_now() const {
    CouplingData d(held_.size());
    for (std::size_t j = 0; j < held_.size(); ++j)
      (force_ ? d[j].force : d[j].displacement) = {state_ + held_[j]};
    return d;
  }
  std::string name_;
  std::vector<std::string>& log_;
  double state_;
  std::vector<double> held_;
  bool force_;
};

// A chain: participant p's last interface faces p + 1's first.
Routing chain(int participants) {
  Routing r(static_cast<std::size_t>(participants));
  for (int p = 0; p < participants; ++p) {
    if (p > 0) r[static_cast<std::size_t>(p)].push_back({p - 1, p - 1 == 0 ? 0 : 1});
    if (p + 1 < participants) r[static_cast<std::size_t>(p)].push_back({p + 1, 0});
  }
  return r;
}

std::vector<CouplingData> zero(int participants) {
  std::vector<CouplingData> in;
  for (int p = 0; p < participants; ++p) {
    const std::size_t n = (p > 0) + (p + 1 < participants);
    in.emplace_back(n);
    for (auto& i : in.back()) i.displacement = {0.0};
  }
  return in;
}

struct Fixture {
  std::vector<std::string> log;
  FakeParticipant s1{"s1", log, 100.0, 1};
  FakeParticipant s2{"s2", log, 200.0, 1};
  std::vector<Participant*> both() { return {&s1, &s2}; }
};

TEST(JacobiSchedule, StartsEveryStepBeforeAwaitingAny) {
  Fixture f;
  JacobiSchedule j(f.both(), chain(2), Feedthrough::kLagged);
  j.initialize(zero(2));
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

TEST(JacobiSchedule, ResolvedReadsAForceAfterItsSenderReceivedTheFreshInput) {
  std::vector<std::string> log;
  FakeParticipant s1{"s1", log, 100.0, 1, /*sends_force=*/true};
  FakeParticipant s2{"s2", log, 200.0, 1};
  JacobiSchedule j({&s1, &s2}, chain(2), Feedthrough::kResolved);
  j.initialize(zero(2));
  log.clear();
  j.advance(0);
  // s1 holds s2's 200, then its force is read: 100 + 200 = 300, and s2 holds
  // that (its first, lagged value 100 is replaced before it steps).
  const std::vector<std::string> expected = {
      "s1.set_inputs(0, 200)", "s2.set_inputs(0, 100)", "s1.outputs",     "s2.set_inputs(0, 300)",
      "s1.start_step(0)",      "s2.start_step(0)",      "s1.finish_step", "s2.finish_step"};
  EXPECT_EQ(log, expected);
}

TEST(JacobiSchedule, LaggedNeverReadsOutputsOutsideASteps) {
  std::vector<std::string> log;
  FakeParticipant s1{"s1", log, 100.0, 1, /*sends_force=*/true};
  FakeParticipant s2{"s2", log, 200.0, 1};
  JacobiSchedule j({&s1, &s2}, chain(2), Feedthrough::kLagged);
  j.initialize(zero(2));
  log.clear();
  j.advance(0);
  EXPECT_EQ(std::count(log.begin(), log.end(), "s1.outputs"), 0);
  EXPECT_EQ(log[1], "s2.set_inputs(0, 100)");
}

TEST(GaussSeidelSchedule, S2StepsWithS1sNewOutputs) {
  Fixture f;
  GaussSeidelSchedule gs(f.both(), chain(2));
  gs.initialize(zero(2));
  f.log.clear();
  gs.advance(0);
  // s1 steps with s2's 200 to 101; s2 then gets 101 + 200 = 301.
  const std::vector<std::string> expected = {"s1.set_inputs(0, 200)", "s1.start_step(0)",
                                             "s1.finish_step",        "s2.set_inputs(0, 301)",
                                             "s2.start_step(0)",      "s2.finish_step"};
  EXPECT_EQ(f.log, expected);
}

TEST(GaussSeidelSchedule, ThreeParticipantsStepInLoadOrderWithTheFreshestValues) {
  std::vector<std::string> log;
  FakeParticipant s1{"s1", log, 100.0, 1}, s2{"s2", log, 200.0, 2}, s3{"s3", log, 300.0, 1};
  GaussSeidelSchedule gs({&s1, &s2, &s3}, chain(3));
  gs.initialize(zero(3));
  log.clear();
  gs.advance(0);
  // s1 gets s2's output at t_n (200); steps to 101 + 200 = 301. s2 gets s1's
  // fresh 301 and s3's old 300; steps to 201: outputs 502 (to s1) and 501 (to
  // s3). s3 gets 501.
  const std::vector<std::string> expected = {
      "s1.set_inputs(0, 200)",      "s1.start_step(0)", "s1.finish_step",
      "s2.set_inputs(0, 301, 300)", "s2.start_step(0)", "s2.finish_step",
      "s3.set_inputs(0, 501)",      "s3.start_step(0)", "s3.finish_step"};
  EXPECT_EQ(log, expected);
}

TEST(JacobiSchedule, ThreeParticipantsAllTakeTheValuesAtTn) {
  std::vector<std::string> log;
  FakeParticipant s1{"s1", log, 100.0, 1}, s2{"s2", log, 200.0, 2}, s3{"s3", log, 300.0, 1};
  JacobiSchedule j({&s1, &s2, &s3}, chain(3), Feedthrough::kLagged);
  j.initialize(zero(3));
  log.clear();
  j.advance(0);
  const std::vector<std::string> expected = {"s1.set_inputs(0, 200)", "s2.set_inputs(0, 100, 300)",
                                             "s3.set_inputs(0, 200)", "s1.start_step(0)",
                                             "s2.start_step(0)",      "s3.start_step(0)",
                                             "s1.finish_step",        "s2.finish_step",
                                             "s3.finish_step"};
  EXPECT_EQ(log, expected);
}

TEST(MakeSchedule, ResolvedFeedthroughOnlyUnderJacobi) {
  Fixture f;
  EXPECT_THROW(make_schedule(Scheme::kGaussSeidel, Feedthrough::kResolved, f.both(), chain(2)),
               std::invalid_argument);
  EXPECT_NE(dynamic_cast<JacobiSchedule*>(
                make_schedule(Scheme::kJacobi, Feedthrough::kResolved, f.both(), chain(2)).get()),
            nullptr);
  EXPECT_NE(
      dynamic_cast<GaussSeidelSchedule*>(
          make_schedule(Scheme::kGaussSeidel, Feedthrough::kLagged, f.both(), chain(2)).get()),
      nullptr);
}

TEST(MakeRouting, EachInterfaceReceivesFromItsPeerOnTheSameCut) {
  Scene scene;
  scene.soil_model = "lumped";
  const auto specs = partition(scene, parse_case("wr-xx+ss-xt-jacobi"));
  const Routing r = make_routing(specs);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0][0].participant, 1);  // the vehicle from the track, on wr
  EXPECT_EQ(r[0][0].interface, 0);
  EXPECT_EQ(r[1][0].participant, 0);  // the track from the vehicle, on wr
  EXPECT_EQ(r[1][1].participant, 2);  // the track from the soil, on ss
  EXPECT_EQ(r[2][0].participant, 1);  // the soil from the track, on ss
  EXPECT_EQ(r[2][0].interface, 1);
}

}  // namespace
}  // namespace railcosim
