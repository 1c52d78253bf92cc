// How the stepping loop ends a run whose participant's integrator gives up
// (a node's STEP_FAILED, or the master's own): diverged only when what the
// participants reported until then shows it, failed otherwise, since a
// participant's word alone is no divergence (a forged STEP_FAILED, a step
// over a node's time limit, a tolerance no step can meet). Unit tests on a
// scripted sequence of macro steps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "newmark.hpp"
#include "run/step_loop.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace step_loop_test {

// Macro steps whose largest |u| follows `u` (one value a step); the step
// after the last gives up.
class Scripted final : public engine::MacroSteps {
 public:
  explicit Scripted(std::vector<double> u) : u_(std::move(u)) {}
  std::vector<StepResult> advance(long n) override {
    if (n >= static_cast<long>(u_.size())) throw StepFailure("the integrator gave up");
    StepResult r;
    r.max_abs_displacement = u_[static_cast<std::size_t>(n)];
    r.finite = std::isfinite(r.max_abs_displacement);
    return {r};
  }

 private:
  std::vector<double> u_;
};

// The run's record after stepping `u` with a largest static displacement of
// 1 mm (the scene's bound: 50 x that).
run::RunRecord stepped(const std::vector<double>& u) {
  Scene scene = test::paper_scene();
  scene.divergence_factor = 50;
  run::RunOptions o;
  o.macro_step = 1e-4;
  run::RunRecord r;
  r.status = "ok";
  Scripted steps(u);
  StepResult start;
  start.max_abs_displacement = 1e-3;
  r.macro_steps = run::step_through(r, steps, scene, o, 100, 50 * 1e-3,
                                    [](long, const std::vector<StepResult>&) {}, {start});
  return r;
}

TEST(StepLoop, AGiveUpAfterGrowthIsADivergence) {
  const run::RunRecord r = stepped({1e-3, 1.5e-3, 2.5e-3});  // 2.5 x the static: grown
  EXPECT_EQ(r.status, "diverged") << r.message;
  EXPECT_EQ(r.macro_steps, 4);
  EXPECT_EQ(r.message, "diverged at macro step 4 (t = 0.0004 s): the integrator gave up");
}

TEST(StepLoop, AGiveUpInTheFirstStepIsJudgedOnTheStart) {
  const run::RunRecord r = stepped({});
  EXPECT_EQ(r.status, "failed") << r.message;
  EXPECT_EQ(r.macro_steps, 1);
  EXPECT_NE(r.message.find("stopped at macro step 1 (t = 0.0001 s): the integrator gave up; not "
                           "judged diverged"),
            std::string::npos)
      << r.message;
}

TEST(StepLoop, AGiveUpWithNothingGrownIsAFailureThatSaysWhy) {
  const run::RunRecord r = stepped({1e-3, 1.2e-3, 1.9e-3});  // under 2 x the static
  EXPECT_EQ(r.status, "failed") << r.message;
  EXPECT_EQ(r.macro_steps, 4);
  EXPECT_EQ(r.message,
            "stopped at macro step 4 (t = 0.0004 s): the integrator gave up; not judged diverged: "
            "the displacements reported until then show no growth (largest |u| 0.0019 m, 1.9 x "
            "the largest static displacement; a divergence needs a value that is not finite or "
            "over 2 x)");
}

}  // namespace step_loop_test
}  // namespace railcosim
