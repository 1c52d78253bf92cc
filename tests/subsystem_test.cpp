#include "subsystem.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cosim_support.hpp"
#include "engine/coupled_statics.hpp"
#include "engine/schedule.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

struct Combo {
  const char* scene;  // under scenes/
  const char* case_name;
  int participant;  // index in load order
};

std::string combo_name(const Combo& c) {
  std::string n = std::string(c.case_name) + "_p" + std::to_string(c.participant);
  for (char& ch : n)
    if (ch == '-' || ch == '+') ch = '_';
  return n;
}

Scene scene_of(const Combo& c) {
  return load_scene(test::source_path(std::string("scenes/") + c.scene));
}

SubsystemConfig config_of(const Combo& c, const Scene& s) {
  SubsystemConfig cfg;
  cfg.participant =
      partition(s, parse_case(c.case_name)).at(static_cast<std::size_t>(c.participant));
  cfg.macro_step = s.macro_step;
  cfg.tolerance = s.tolerance;
  return cfg;
}

// Inputs for step n: the static inputs, perturbed by a smooth signal so that
// every subsystem really moves.
CouplingData inputs_at(const CouplingData& base, long n) {
  CouplingData in = base;
  const double f = 1.0 + 0.05 * std::sin(0.3 * static_cast<double>(n));
  for (InterfaceData& i : in) {
    for (auto& x : i.displacement) x *= f;
    for (auto& x : i.velocity) x = 1e-3 * std::cos(0.3 * static_cast<double>(n));
    for (auto& x : i.force) x *= f;
  }
  return in;
}

// The inputs a participant holds at the coupled static state of its case.
CouplingData static_inputs(const Scene& scene, const Combo& c) {
  return test::inproc_case_at_statics(scene, c.case_name)
      .statics.inputs.at(static_cast<std::size_t>(c.participant));
}

class SubsystemTest : public ::testing::TestWithParam<Combo> {};

TEST_P(SubsystemTest, SaveRestoreAndStepAgainIsBitwiseIdentical) {
  const Combo c = GetParam();
  const Scene scene = scene_of(c);
  const CouplingData base = static_inputs(scene, c);
  Subsystem sub(scene, config_of(c, scene));
  sub.initialize(base);
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
  EXPECT_EQ(results_again.fields, results_first.fields);
  EXPECT_EQ(results_again.micro_steps, results_first.micro_steps);
}

TEST_P(SubsystemTest, StartsAtRestInTheStaticState) {
  const Combo c = GetParam();
  const Scene scene = scene_of(c);
  Subsystem sub(scene, config_of(c, scene));
  sub.initialize(static_inputs(scene, c));
  // Held at the other sides' static values, nothing accelerates: what is
  // left comes from the interface values, converged to 1e-13 relative, acting
  // on the light rail DOFs (a millionth of g).
  EXPECT_LT(sub.integrator_state().a.cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_TRUE(sub.integrator_state().v.isZero());
}

INSTANTIATE_TEST_SUITE_P(
    AllSides, SubsystemTest,
    ::testing::Values(
        Combo{"paper.toml", "wr-xx-jacobi", 0}, Combo{"paper.toml", "wr-xx-jacobi", 1},
        Combo{"paper.toml", "wr-xt-jacobi", 0}, Combo{"paper.toml", "wr-xt-jacobi", 1},
        Combo{"paper.toml", "rs-xx-jacobi", 0}, Combo{"paper.toml", "rs-xx-jacobi", 1},
        Combo{"paper.toml", "rs-xt-jacobi", 0}, Combo{"paper.toml", "rs-xt-jacobi", 1},
        Combo{"soil.toml", "ss-xx-jacobi", 0}, Combo{"soil.toml", "ss-xx-jacobi", 1},
        Combo{"soil.toml", "ss-xt-jacobi", 0}, Combo{"soil.toml", "ss-xt-jacobi", 1},
        Combo{"soil.toml", "wr-xt+ss-xx-jacobi", 1}),
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
  const Combo combo{"paper.toml", "rs-xx-jacobi", 1};
  const SubsystemConfig cfg = config_of(combo, scene);
  Subsystem sub(scene, cfg);
  expect_rejected([&] { sub.start_step(0); },
                  "start_step(0) rejected: initialize() must come first");
  expect_rejected([&] { sub.outputs(); }, "initialize() must come first");
  expect_rejected([&] { sub.save(); }, "initialize() must come first");
  const CouplingData in = static_inputs(scene, combo);
  sub.initialize(in);
  expect_rejected([&] { sub.initialize(in); }, "initialize() may only be called once");
  expect_rejected([&] { sub.statics(in); }, "the statics come before initialize()");
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
  const Combo combo{"paper.toml", "rs-xx-jacobi", 1};
  Subsystem sub(scene, config_of(combo, scene));
  sub.initialize(static_inputs(scene, combo));
  CouplingData wrong(1);
  wrong[0].displacement = {0.0, 0.0, 0.0};
  wrong[0].velocity.assign(50, 0.0);
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, wrong); },
                                 "expected 50 rs displacement value(s), got 3");
  wrong[0].displacement.assign(50, 0.0);
  wrong[0].displacement[7] = NAN;
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, wrong); },
                                 "non-finite rs displacement value");
  wrong[0].displacement[7] = 0.0;
  wrong[0].force.assign(50, 1.0);
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, wrong); },
                                 "expected 0 rs force value(s), got 50");
  expect_rejected<BadInputError>([&] { sub.set_inputs(0, CouplingData(2)); },
                                 "expected values for 1 interface(s), got 2");
}

}  // namespace
}  // namespace railcosim
