#include "newmark.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "statics.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

// A single-DOF oscillator m u'' + c u' + k u = 0, u(0) = 1, u'(0) = 0.
struct Oscillator {
  double m = 1.0, k = 4.0 * M_PI * M_PI, zeta = 0.05;  // 1 Hz, 5% damping
  double omega() const { return std::sqrt(k / m); }
  double c() const { return 2.0 * zeta * std::sqrt(k * m); }
  double exact(double t) const {
    const double w = omega(), wd = w * std::sqrt(1.0 - zeta * zeta);
    return std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
  }
  Structure structure() const {
    Structure s;
    s.layout.size = 1;
    s.M = SymmetricBandMatrix(1, 0);
    s.C = SymmetricBandMatrix(1, 0);
    s.K = SymmetricBandMatrix(1, 0);
    s.M.add(0, 0, m);
    s.C.add(0, 0, c());
    s.K.add(0, 0, k);
    s.load = Vector::Zero(1);
    return s;
  }
};

// Integrates to t = 1 s in intervals H, returns max |u - exact| at the ends of
// the intervals.
double oscillator_error(double H, double tolerance) {
  const Oscillator o;
  Structure s = o.structure();
  Newmark nm(s, H, tolerance);
  nm.set_state(Vector::Ones(1), Vector::Zero(1), 0.0);
  const long steps = std::lround(1.0 / H);
  double err = 0;
  for (long n = 0; n < steps; ++n) {
    nm.advance(n * H, (n + 1) * H);
    err = std::max(err, std::abs(nm.state().u[0] - o.exact((n + 1) * H)));
  }
  return err;
}

TEST(Newmark, SecondOrderOnTheDampedOscillator) {
  std::vector<double> h, err;
  for (double step = 1.0 / 20; step >= 1.0 / 320; step /= 2) {  // four halvings
    h.push_back(step);
    err.push_back(oscillator_error(step, 0.0));
  }
  const double order = test::fitted_order(h, err);
  EXPECT_NEAR(order, 2.0, 0.1) << "errors " << err[0] << " ... " << err.back();
}

TEST(Newmark, ConservesTheEnergyOfAnUndampedLinearSystem) {
  // The paper's track (rail, pads, sleepers, ballast) with its damping removed,
  // released from the statically loaded shape.
  const Scene scene = test::paper_scene();
  // The track side of a wheel/rail X-T cut: loaded by the static wheel load.
  ParticipantSpec track;
  track.role = "track";
  track.parts.add(Component::kRail);
  track.parts.add(Component::kSleepers);
  track.interfaces.push_back({find_cut("wr"), CutSide::kLower, Coupling::kXT, 0, "vehicle"});
  Structure s = assemble(scene, track);
  s.C = SymmetricBandMatrix(s.layout.size, s.C.half_bandwidth());
  s.contacts.front().prescribed_force = scene.load();
  const Vector u0 = solve_static(s, Vector::Zero(s.layout.size));
  s.contacts.clear();  // released: no load from then on

  auto energy = [&](const NewmarkState& x) {
    Vector Mv, Ku;
    s.M.multiply(x.v, Mv);
    s.K.multiply(x.u, Ku);
    return 0.5 * x.v.dot(Mv) + 0.5 * x.u.dot(Ku);
  };
  const double H = 1e-4;
  Newmark nm(s, H, 0.0);
  nm.set_state(u0, Vector::Zero(s.layout.size), 0.0);
  const double e0 = energy(nm.state());
  double worst = 0;
  for (long n = 0; n < 10000; ++n) {
    nm.advance(n * H, (n + 1) * H);
    worst = std::max(worst, std::abs(energy(nm.state()) - e0) / e0);
  }
  EXPECT_LT(worst, 1e-10);
  // The state did move: the energy is not trivially conserved at rest.
  EXPECT_GT((nm.state().u - u0).norm(), 1e-2 * u0.norm());
}

TEST(Newmark, AdaptiveErrorFallsWithTheTolerance) {
  std::vector<double> errors;
  for (double tol : {1e-3, 1e-5, 1e-7, 1e-9}) {
    errors.push_back(oscillator_error(0.25, tol));
    if (errors.size() > 1) {
      EXPECT_LT(errors.back(), errors[errors.size() - 2]) << "tol " << tol;
    }
  }
  // Six decades of tolerance buy at least three of global error.
  EXPECT_LT(errors.back(), 1e-3 * errors.front());
  // A fixed step of H = 0.25 s (4 steps per period) is far worse.
  EXPECT_GT(oscillator_error(0.25, 0.0), 100 * errors.back());
}

TEST(Newmark, AdaptiveStepsLandExactlyOnEveryRequestedTime) {
  const Oscillator o;
  Structure s = o.structure();
  const double H = 0.1;  // not a binary fraction: ends are computed as n * H
  Newmark nm(s, H, 1e-8);
  std::vector<double> ends;
  std::vector<int> levels;
  nm.set_step_observer([&](double t, int level) {
    ends.push_back(t);
    levels.push_back(level);
  });
  nm.set_state(Vector::Ones(1), Vector::Zero(1), 0.0);
  for (long n = 0; n < 10; ++n) {
    const double t0 = n * H, t1 = (n + 1) * H;
    ends.clear();
    levels.clear();
    nm.advance(t0, t1);
    ASSERT_FALSE(ends.empty());
    EXPECT_EQ(ends.back(), t1) << "interval " << n;  // bitwise
    // The steps tile the interval: their lengths H / 2^level add up to H exactly.
    long long ticks = 0;
    for (int level : levels) ticks += 1LL << (Newmark::kMaxLevel - level);
    EXPECT_EQ(ticks, 1LL << Newmark::kMaxLevel) << "interval " << n;
    for (std::size_t i = 1; i < ends.size(); ++i) EXPECT_LT(ends[i - 1], ends[i]);
    EXPECT_GT(ends.front(), t0);
  }
  // With this tolerance the controller refined below H at least once.
  EXPECT_GT(nm.state().micro_steps, 10);
}

}  // namespace
}  // namespace railcosim
