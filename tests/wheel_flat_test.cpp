#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "excitation_toml.hpp"
#include "hertz.hpp"
#include "irregularity.hpp"
#include "scene.hpp"
#include "wheel_flat.hpp"

namespace railcosim {
namespace wheel_flat_test {

constexpr double kPi = std::numbers::pi;

WheelFlatSpec flat(double length, double diameter, double angle_deg, FlatShape shape) {
  WheelFlatSpec s;
  s.length = length;
  s.diameter = diameter;
  s.angle = angle_deg * kPi / 180.0;
  s.shape = shape;
  return s;
}

TEST(WheelFlat, DepthIsTheChordGeometry) {
  const double L = 0.05, D = 0.92, R = D / 2;
  const WheelFlat f(flat(L, D, 0.0, FlatShape::chord));
  EXPECT_NEAR(f.depth(), R - std::sqrt(R * R - L * L / 4), 1e-16);
  // First-order form L^2 / (4 D): off by (L/D)^2 / 4 relative, 0.07 % here.
  EXPECT_NEAR(f.depth(), L * L / (4 * D), 1e-3 * f.depth());
  // The deepest point meets the rail at s = 0 (angle 0); the edges at
  // s = +-R alpha leave no loss, and beyond them the wheel is round.
  const double alpha = std::asin(L / D);
  EXPECT_NEAR(f.loss(0.0), f.depth(), 1e-16);
  EXPECT_NEAR(f.loss(R * alpha * (1 - 1e-12)), 0.0, 1e-14);
  EXPECT_EQ(f.loss(R * alpha * 1.01), 0.0);
  EXPECT_EQ(f.loss(-R * alpha * 1.01), 0.0);
  EXPECT_GT(f.loss(0.5 * R * alpha), 0.0);
  EXPECT_LT(f.loss(0.5 * R * alpha), f.depth());
}

TEST(WheelFlat, RoundedFlatHasTheSameDepthAndSmoothEdges) {
  const WheelFlat f(flat(0.05, 0.92, 0.0, FlatShape::rounded));
  const WheelFlat c(flat(0.05, 0.92, 0.0, FlatShape::chord));
  EXPECT_DOUBLE_EQ(f.depth(), c.depth());
  EXPECT_NEAR(f.loss(0.0), f.depth(), 1e-16);
  const double edge = 0.05 / 2;  // the arc +-L/2
  EXPECT_NEAR(f.loss(edge * (1 - 1e-9)), 0.0, 1e-12);
  EXPECT_NEAR(f.loss_slope(edge * (1 - 1e-9)), 0.0, 1e-6);
  EXPECT_EQ(f.loss(edge * 1.001), 0.0);
}

TEST(WheelFlat, RepeatsOncePerRevolutionFromTheGivenAngle) {
  for (FlatShape shape : {FlatShape::chord, FlatShape::rounded}) {
    const WheelFlat f(flat(0.06, 0.84, 90.0, shape));
    EXPECT_DOUBLE_EQ(f.circumference(), kPi * 0.84);
    // A quarter turn (R pi/2 rolled) brings the flat's centre to the rail.
    EXPECT_NEAR(f.impact_position(0), 0.42 * kPi / 2, 1e-15);
    for (int n = 0; n < 50; ++n) {
      const double s = f.impact_position(n);
      EXPECT_NEAR(s, 0.42 * kPi / 2 + n * kPi * 0.84, 1e-12);
      EXPECT_NEAR(f.loss(s), f.depth(), 1e-12 * f.depth() + 1e-15) << n;
      // Half a revolution later the wheel is round.
      EXPECT_EQ(f.loss(s + 0.5 * f.circumference()), 0.0);
    }
    EXPECT_EQ(f.loss(0.0), 0.0);  // at t = 0 the flat is a quarter turn away
    // Periodic: f(s + pi D) = f(s) over a flat's passage.
    for (double s = 0.6; s < 0.72; s += 0.001)
      EXPECT_NEAR(f.loss(s + 7 * f.circumference()), f.loss(s), 1e-12 * f.depth());
  }
}

TEST(WheelFlat, SlopeIsTheDerivativeOfTheLoss) {
  for (FlatShape shape : {FlatShape::chord, FlatShape::rounded}) {
    const WheelFlat f(flat(0.05, 0.92, 0.0, shape));
    constexpr double h = 1e-7;  // central difference: error ~h^2 f''' ~ 1e-10
    for (double s = -0.02; s <= 0.02; s += 0.00137) {
      const double num = (f.loss(s + h) - f.loss(s - h)) / (2 * h);
      EXPECT_NEAR(f.loss_slope(s), num, 1e-6) << s;
    }
  }
}

// A wheel of mass m pressed on a rigid rail by its weight, rolling at v with
// a flat: one impact (a force peak well above the weight) per revolution. A
// dashpot c on the wheel (30 % of critical for the linearised contact, whose
// frequency is ~130 Hz) lets the ringing die out between impacts.
TEST(WheelFlat, RollingWheelFeelsOnePeakPerRevolution) {
  const double m = 1000.0, g = 9.81, K_H = 92.86e9, v = 20.0;
  const double k_lin = 1.5 * K_H * std::sqrt(hertz_penetration(K_H, m * g));
  const double c = 2 * 0.3 * std::sqrt(k_lin * m);
  const WheelFlat f(flat(0.05, 0.92, 30.0, FlatShape::chord));
  const double period = f.circumference() / v;
  // Explicit central differences on m q'' = m g - F(q - loss(v t)): the
  // contact's period 2 pi sqrt(m / k_lin) ~ 0.1 ms; dt = 1 us resolves it.
  const double dt = 1e-6, t_end = 4.5 * period;
  double q = hertz_penetration(K_H, m * g), q_prev = q;
  std::vector<double> peaks;
  double F_prev = m * g, F_prev2 = m * g;
  for (double t = 0; t < t_end; t += dt) {
    const double F = hertz_force(K_H, contact_penetration(q, 0.0, 0.0, f.loss(v * t)));
    const double q_next = 2 * q - q_prev + dt * dt * (g - (F + c * (q - q_prev) / dt) / m);
    q_prev = q;
    q = q_next;
    // A local maximum above twice the weight is an impact.
    if (F_prev > F_prev2 && F_prev >= F && F_prev > 2 * m * g) {
      if (peaks.empty() || t - peaks.back() > 0.5 * period) peaks.push_back(t);
    }
    F_prev2 = F_prev;
    F_prev = F;
  }
  // The flat first meets the rail after a 30 degree turn, then every turn:
  // five impacts in 4.5 periods, each just after the flat's centre passes.
  ASSERT_EQ(peaks.size(), 5u);
  EXPECT_NEAR(peaks[0], f.impact_position(0) / v, 0.02 * period);
  for (std::size_t i = 1; i < peaks.size(); ++i)
    EXPECT_NEAR(peaks[i] - peaks[i - 1], period, 0.01 * period);  // same impact each turn
}

WheelFlatSpec parse(const std::string& text) {
  const toml::table root = toml::parse(text, std::string_view("s.toml"));
  return parse_wheel_flat(*root["wheel_flat"].as_table(), "s.toml", 4);
}

TEST(WheelFlatToml, ReadsKeysAndRejectsMistakes) {
  const WheelFlatSpec s = parse(
      "[wheel_flat]\nlength = 0.05\nwheel_diameter = 0.92\nangle_deg = 180.0\n"
      "shape = \"rounded\"\nwheel = 3\n");
  EXPECT_DOUBLE_EQ(s.length, 0.05);
  EXPECT_DOUBLE_EQ(s.angle, kPi);
  EXPECT_EQ(s.shape, FlatShape::rounded);
  EXPECT_EQ(s.wheel, 2);
  auto expect_error = [](const std::string& text, const std::string& fragment) {
    try {
      parse(text);
      ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("s.toml: key 'wheel_flat." + fragment),
                std::string::npos)
          << e.what();
    }
  };
  expect_error("[wheel_flat]\nlength = 0.05\nwheel_diameter = 0.92\nwheel = 5\n",
               "wheel': must be a wheel of the vehicle, 1 to 4");
  expect_error("[wheel_flat]\nlength = 1.0\nwheel_diameter = 0.92\n", "length': must be shorter");
  expect_error("[wheel_flat]\nlength = 0.05\nwheel_diameter = 0.92\ndepth = 1e-3\n",
               "depth': unknown key");
  expect_error("[wheel_flat]\nwheel_diameter = 0.92\n", "length': missing");
}

}  // namespace wheel_flat_test
}  // namespace railcosim
