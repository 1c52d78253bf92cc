// The automatic track length: the wheel's path plus a margin that follows
// from the tolerance on the deflection under the wheel.
#include <gtest/gtest.h>

#include <cmath>

#include "monolithic.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

// The deflection under the wheel at t_end.
double under_wheel(const Scene& s) {
  MonolithicModel m(s, s.macro_step, s.tolerance);
  const long N = s.macro_steps();
  for (long n = 0; n < N; ++n) m.advance(n);
  return m.rail_under_wheel(static_cast<double>(N) * s.macro_step);
}

// A track long enough to stand for an infinite one: 100 sleepers (60 m), the
// wheel starting 20 m in and ending about 19 m before the far end (over 20
// characteristic lengths 1/beta from both ends).
Scene long_track(double end_time) {
  Scene s = test::paper_scene();
  s.sleeper_count = 100;
  s.initial_position = 20.0;
  s.end_time = end_time;
  s.validate();
  return s;
}

Scene auto_track(double end_time, double margin_tolerance) {
  Scene s = long_track(end_time);
  s.auto_length = true;
  s.margin_tolerance = margin_tolerance;
  s.size_track(20.0);
  s.validate();
  return s;
}

TEST(TrackLength, MarginFollowsFromTheTolerance) {
  const Scene s = auto_track(0.25, 1e-4);
  EXPECT_NEAR(s.margin, std::log(1e4) / s.winkler_beta(), 1e-12);
  EXPECT_NEAR(s.winkler_beta(), 1.222, 1e-3);
  // The rail covers the path plus the margin on each side, on the sleeper grid.
  const double x_end = 20.0 + s.speed * s.end_time;
  EXPECT_LE(s.rail_start, 20.0 - s.margin);
  EXPECT_GE(s.rail_start + s.track_length(), x_end + s.margin);
  EXPECT_LT(s.track_length(), x_end - 20.0 + 2 * s.margin + 2 * s.sleeper_spacing);
  EXPECT_NEAR(std::remainder(s.rail_start, s.sleeper_spacing), 0.0, 1e-9);
  EXPECT_NEAR(s.initial_position + s.rail_start, 20.0, 1e-12);
}

// With its default margin (tolerance 1e-4), and with looser ones, the
// truncated track gives the deflection under the wheel of the long track to
// within that tolerance.
class TrackLengthTolerance : public ::testing::TestWithParam<double> {};

TEST_P(TrackLengthTolerance, DeflectionUnderTheWheelWithinTheTolerance) {
  const double tol = GetParam();
  for (double end_time : {0.05, 0.25}) {
    const double full = under_wheel(long_track(end_time));
    const Scene a = auto_track(end_time, tol);
    const double truncated = under_wheel(a);
    EXPECT_LT(std::abs(truncated - full) / std::abs(full), tol)
        << "t_end " << end_time << " s, " << a.sleeper_count << " sleepers instead of 100";
    EXPECT_LT(a.sleeper_count, 100);
  }
}

INSTANTIATE_TEST_SUITE_P(Tolerances, TrackLengthTolerance, ::testing::Values(1e-2, 1e-3, 1e-4));

TEST(TrackLength, SceneFileAcceptsAuto) {
  std::string text = R"(
[vehicle]
mass = 11250.0
hertz_constant = 92.86e9
speed_kmh = 300.0
initial_position = 2.0
[rail]
young_modulus = 210e9
second_moment = 1987e-8
area = 63.8e-4
density = 7850.0
elements_per_span = 2
[railpad]
stiffness = 180e6
damping = 28e3
[sleepers]
mass = 90.84
spacing = 0.6
count = "auto"
[ballast]
stiffness = 25.5e6
damping = 40e3
[simulation]
gravity = 9.81
end_time = 0.05
macro_step = 1e-4
tolerance = 1e-7
)";
  const Scene s = parse_scene(text, "auto.toml");
  EXPECT_TRUE(s.auto_length);
  EXPECT_NEAR(s.initial_position + s.rail_start, 2.0, 1e-12);
  EXPECT_LT(s.rail_start, 0.0);  // the margin reaches behind x = 0
  const std::string fixed = std::string(text).replace(text.find("\"auto\""), 6, "50");
  EXPECT_EQ(parse_scene(fixed, "fixed.toml").sleeper_count, 50);
  std::string bad = text;
  bad.replace(bad.find("count = \"auto\""), 14, "count = \"auto\"\nmargin_tolerance = 2.0");
  EXPECT_THROW(parse_scene(bad, "bad.toml"), SceneError);
  std::string stray = std::string(text).replace(text.find("\"auto\""), 6, "50");
  stray.replace(stray.find("count = 50"), 10, "count = 50\nmargin_tolerance = 1e-3");
  try {
    parse_scene(stray, "stray.toml");
    FAIL() << "margin_tolerance with a fixed count must be refused";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("'sleepers.margin_tolerance': applies only"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace railcosim
