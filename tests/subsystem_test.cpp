#include "subsystem.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

namespace railcosim {
namespace {

struct Combo {
  Split split;
  Side side;
  Coupling coupling;
};

std::string combo_name(const Combo& c) {
  return to_string(c.split) + "_" + to_string(c.side) + "_" + to_string(c.coupling);
}

SubsystemConfig config_of(const Combo& c, const Scene& s) {
  return {c.split, c.side, c.coupling, s.macro_step, s.tolerance};
}

// Inputs for step n: the static inputs, perturbed by a smooth signal so that
// every subsystem really moves.
CouplingData inputs_at(const CouplingData& base, long n) {
  CouplingData in = base;
  const double f = 1.0 + 0.05 * std::sin(0.3 * static_cast<double>(n));
  for (auto& x : in.displacement) x *= f;
  for (auto& x : in.velocity) x = 1e-3 * std::cos(0.3 * static_cast<double>(n));
  for (auto& x : in.force) x *= f;
  return in;
}

// The inputs a fresh subsystem of this kind holds at t = 0.
CouplingData static_inputs(const Scene& scene, const Combo& c) {
  Subsystem other(scene, {c.split, c.side == Side::kS1 ? Side::kS2 : Side::kS1, c.coupling,
                          scene.macro_step, scene.tolerance});
  return other.initialize().outputs;
}

class SubsystemTest : public ::testing::TestWithParam<Combo> {};

TEST_P(SubsystemTest, SaveRestoreAndStepAgainIsBitwiseIdentical) {
  const Scene scene = test::paper_scene();
  const Combo c = GetParam();
  const CouplingData base = static_inputs(scene, c);
  Subsystem sub(scene, config_of(c, scene));
  sub.initialize();
  long n = 0;
  for (; n < 20; ++n) {
    sub.set_inputs(n, inputs_at(base, n));
    sub.step(n);
  }
  const ParticipantState snapshot = sub.save();
  std::vector<CouplingData> first;
  for (long k = n; k < n + 30; ++k) {
    sub.set_inputs(k, inputs_at(base, k));
    first.push_back(sub.step(k).outputs);
  }
  const ParticipantState end_first = sub.save();
  const ParticipantResults results_first = sub.results();
  EXPECT_NE(end_first, snapshot);

  sub.restore(snapshot);
  EXPECT_EQ(sub.save(), snapshot);
  for (long k = n; k < n + 30; ++k) {
    sub.set_inputs(k, inputs_at(base, k));
    EXPECT_EQ(sub.step(k).outputs, first[static_cast<std::size_t>(k - n)]) << "step " << k;
  }
  EXPECT_EQ(sub.save(), end_first);  // operator== on doubles: bitwise for finite values
  const ParticipantResults results_again = sub.results();
  EXPECT_EQ(results_again.rail_deflection, results_first.rail_deflection);
  EXPECT_EQ(results_again.micro_steps, results_first.micro_steps);
}

TEST_P(SubsystemTest, StartsAtRestInTheStaticState) {
  const Scene scene = test::paper_scene();
  const Combo c = GetParam();
  Subsystem sub(scene, config_of(c, scene));
  sub.initialize();
  // Held at the other side's static values, nothing accelerates.
  EXPECT_LT(sub.integrator_state().a.cwiseAbs().maxCoeff(), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(AllSides, SubsystemTest,
                         ::testing::Values(Combo{Split::kWheelRail, Side::kS1, Coupling::kXX},
                                           Combo{Split::kWheelRail, Side::kS2, Coupling::kXX},
                                           Combo{Split::kWheelRail, Side::kS1, Coupling::kXT},
                                           Combo{Split::kWheelRail, Side::kS2, Coupling::kXT},
                                           Combo{Split::kRailSleepers, Side::kS1, Coupling::kXX},
                                           Combo{Split::kRailSleepers, Side::kS2, Coupling::kXX},
                                           Combo{Split::kRailSleepers, Side::kS1, Coupling::kXT},
                                           Combo{Split::kRailSleepers, Side::kS2, Coupling::kXT}),
                         [](const auto& param_info) { return combo_name(param_info.param); });

// Expects `call` to throw Error with `text` in its message.
template <typename Error = CallOrderError, typename F>
void expect_rejected(F&& call, const std::string& text) {
  try {
    call();
    ADD_FAILURE() << "not rejected; expected: " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(SubsystemCallOrder, OutOfOrderCallsAreRejected) {
  const Scene scene = test::paper_scene();
  const SubsystemConfig cfg{Split::kRailSleepers, Side::kS2, Coupling::kXX, scene.macro_step,
                            scene.tolerance};
  Subsystem sub(scene, cfg);
  expect_rejected([&] { sub.start_step(0); },
                  "start_step(0) rejected: initialize() must come first");
  expect_rejected([&] { sub.outputs(); }, "initialize() must come first");
  expect_rejected([&] { sub.save(); }, "initialize() must come first");
  const CouplingData in = static_inputs(scene, {cfg.split, cfg.side, cfg.coupling});
  sub.initialize();
  expect_rejected([&] { sub.initialize(); }, "initialize() may only be called once");
  expect_rejected([&] { sub.start_step(0); }, "set_inputs() must come first for every macro step");
  expect_rejected([&] { sub.finish_step(); }, "no step was started");
  expect_rejected([&] { sub.set_inputs(3, in); },
                  "set_inputs(3) rejected: the subsystem is at macro step 0");
  sub.set_inputs(0, in);
  expect_rejected([&] { sub.start_step(1); },
                  "start_step(1) rejected: the subsystem is at macro step 0");
  sub.start_step(0);
  expect_rejected([&] { sub.set_inputs(0, in); }, "a step is in progress");
  expect_rejected([&] { sub.start_step(0); }, "the previous step has not been finished");
  sub.finish_step();
  expect_rejected([&] { sub.start_step(1); }, "set_inputs() must come first");
}

TEST(SubsystemCallOrder, InputsThatDoNotFitAreRejected) {
  const Scene scene = test::paper_scene();
  Subsystem sub(
      scene, {Split::kRailSleepers, Side::kS2, Coupling::kXX, scene.macro_step, scene.tolerance});
  sub.initialize();
  CouplingData wrong;
  wrong.displacement = {0.0, 0.0, 0.0};
  wrong.velocity.assign(50, 0.0);
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, wrong); },
                                 "expected 50 displacement value(s), got 3");
  wrong.displacement.assign(50, 0.0);
  wrong.displacement[7] = NAN;
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, wrong); },
                                 "non-finite displacement value");
  wrong.displacement[7] = 0.0;
  wrong.force.assign(50, 1.0);
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, wrong); },
                                 "expected 0 force value(s), got 50");
}

}  // namespace
}  // namespace railcosim
