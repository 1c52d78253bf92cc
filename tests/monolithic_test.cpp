#include <gtest/gtest.h>

#include <algorithm>

#include "run/runner.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace {

run::RunRecord monolithic(const Scene& scene, double tolerance) {
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = tolerance;
  return run::run_monolithic(scene, o);
}

TEST(Monolithic, DeflectionSelfConvergesAsTheToleranceTightens) {
  const Scene scene = test::paper_scene();
  const run::RunRecord reference = monolithic(scene, 1e-10);
  double previous = INFINITY;
  for (double tol : {1e-7, 1e-8, 1e-9}) {
    const double err =
        verdict::deflection_error(monolithic(scene, tol).deflection, reference.deflection).max_abs;
    EXPECT_LT(err, previous) << "tolerance " << tol;
    previous = err;
  }
  // At the scene's own tolerance the deflection is right to four digits.
  const run::RunRecord own = monolithic(scene, scene.tolerance);
  EXPECT_LT(verdict::deflection_error(own.deflection, reference.deflection).rel_l2, 1e-4);
}

TEST(Monolithic, PeakDeflectionFollowsTheWheel) {
  const Scene scene = test::paper_scene();
  const run::RunRecord r = monolithic(scene, scene.tolerance);
  ASSERT_EQ(r.deflection.size(), 101u);
  const auto peak = std::max_element(r.deflection.begin(), r.deflection.end());
  const double x_peak = r.x[static_cast<std::size_t>(peak - r.deflection.begin())];
  const double x_wheel = scene.initial_position + scene.speed * scene.end_time;  // 22.83 m
  EXPECT_NEAR(x_wheel, 22.833, 1e-3);
  EXPECT_LE(std::abs(x_peak - x_wheel), scene.element_length());
  EXPECT_GT(*peak, 1.80e-3);
  EXPECT_LT(*peak, 1.90e-3);
}

TEST(Monolithic, HistoryHasEveryOutputStep) {
  const Scene scene = test::paper_scene();
  const run::RunRecord r = monolithic(scene, scene.tolerance);
  ASSERT_EQ(r.history.size(), 2501u);
  EXPECT_EQ(r.history.front().t, 0.0);
  EXPECT_EQ(r.history.back().t, 2500 * scene.macro_step);
  // The run starts at rest in the static state: the contact carries m g.
  EXPECT_NEAR(r.history.front().contact_force, scene.load(), 1e-9 * scene.load());
}

}  // namespace
}  // namespace railcosim
