// Waveforms: interpolation exact for polynomials of its degree, and the order
// of accuracy each degree gives a coupling, measured on two masses coupled by
// a spring against the closed-form solution.
#include "waveform.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "test_support.hpp"

namespace railcosim {
namespace {

double poly(const std::vector<double>& c, double t) {
  double v = 0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) v = v * t + *it;
  return v;
}

// Uneven sample times, as an adaptive sender's substeps are.
const std::vector<double> kTimes = {0.0, 0.1, 0.25, 0.3, 0.55, 0.8};

Waveform sampled(int degree, const std::vector<double>& c) {
  Waveform w(degree, 2);
  for (double t : kTimes) w.add(t, {poly(c, t), -2.0 * poly(c, t)});
  return w;
}

TEST(Waveform, ExactForPolynomialsOfItsDegree) {
  const std::vector<double> coefficients = {0.7, -1.3, 2.1, -0.9};
  for (int p = 0; p <= Waveform::kMaxDegree; ++p) {
    const std::vector<double> c(coefficients.begin(), coefficients.begin() + p + 1);
    const Waveform w = sampled(p, c);
    EXPECT_EQ(w.effective_degree(), p);
    for (int i = 0; i <= 64; ++i) {
      const double t = -0.05 + 0.9 * i / 64.0;  // beyond both ends too
      const std::vector<double> v = w.at(t);
      EXPECT_NEAR(v[0], poly(c, t), 1e-12) << "degree " << p << " at t = " << t;
      EXPECT_NEAR(v[1], -2.0 * poly(c, t), 1e-12) << "degree " << p << " at t = " << t;
    }
  }
}

TEST(Waveform, NotExactOneDegreeHigher) {
  const std::vector<double> coefficients = {0.7, -1.3, 2.1, -0.9, 1.7};
  for (int p = 0; p <= Waveform::kMaxDegree; ++p) {
    const std::vector<double> c(coefficients.begin(), coefficients.begin() + p + 2);
    const Waveform w = sampled(p, c);
    double worst = 0;
    for (int i = 0; i <= 64; ++i) {
      const double t = 0.8 * i / 64.0;
      worst = std::max(worst, std::abs(w.at(t)[0] - poly(c, t)));
    }
    EXPECT_GT(worst, 1e-4) << "degree " << p;
  }
}

TEST(Waveform, DegreeFallsWithFewSamplesAndHoldsOne) {
  Waveform w(3, 1);
  w.add(1.0, {2.0});
  EXPECT_EQ(w.effective_degree(), 0);
  EXPECT_EQ(w.at(1.7)[0], 2.0);
  w.add(2.0, {4.0});
  EXPECT_EQ(w.effective_degree(), 1);
  EXPECT_DOUBLE_EQ(w.at(1.25)[0], 2.5);
  w.keep_last();
  EXPECT_EQ(w.samples(), 1u);
  EXPECT_EQ(w.first_time(), 2.0);
}

TEST(Waveform, RefusesWhatItCannotHold) {
  EXPECT_THROW(Waveform(4, 1), std::invalid_argument);
  EXPECT_THROW(Waveform(-1, 1), std::invalid_argument);
  Waveform w(1, 2);
  EXPECT_THROW(w.at(0.0), std::logic_error);
  w.add(0.0, {1.0, 2.0});
  EXPECT_THROW(w.add(0.0, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(w.add(1.0, {1.0}), std::invalid_argument);
}

// Two masses on springs to the ground, coupled by a spring:
//   m1 x1'' = -k1 x1 - kc (x1 - x2),   m2 x2'' = -k2 x2 - kc (x2 - x1),
// x1(0) = 1, the rest at rest. Each participant integrates its own mass with
// RK4 at `substeps` equal substeps per window, receives the other's
// displacement as a waveform of its substep samples, and the window is
// iterated (Gauss-Seidel waveform relaxation) until the samples agree to
// round-off. The coupling error is then that of the interpolation alone.
struct TwoMasses {
  double m1 = 1.0, m2 = 2.0, k1 = 40.0, k2 = 25.0, kc = 30.0;

  // Closed form at t: K phi = w^2 M phi, x(t) = Phi cos(w t) Phi^T M x0.
  double x1_exact(double t) const {
    Eigen::Matrix2d K, M;
    K << k1 + kc, -kc, -kc, k2 + kc;
    M << m1, 0, 0, m2;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> e(K, M);
    const Eigen::Matrix2d& phi = e.eigenvectors();
    Eigen::Vector2d q = phi.transpose() * M * Eigen::Vector2d(1.0, 0.0);
    for (int i = 0; i < 2; ++i) q[i] *= std::cos(std::sqrt(e.eigenvalues()[i]) * t);
    return (phi * q)[0];
  }
};

struct Side {
  double m, k, kc, x, v;
  // One window [t0, t0 + H] in `n` RK4 substeps against the other's
  // displacement `other`; returns this side's displacement samples.
  Waveform advance(double t0, double H, int n, const Waveform& other, int degree) {
    Waveform out(degree, 1);
    out.add(t0, {x});
    const double h = H / n;
    std::vector<double> xo;
    auto acc = [&](double t, double xs) {
      other.at(t, xo);
      return (-k * xs - kc * (xs - xo[0])) / m;
    };
    for (int s = 0; s < n; ++s) {
      const double t = t0 + s * h;
      test::rk4_step(x, v, t, h, acc);
      out.add(t0 + (s + 1 == n ? H : (s + 1) * h), {x});
    }
    return out;
  }
};

double coupled_error(int degree, double H, double T, int substeps) {
  const TwoMasses sys;
  Side a{sys.m1, sys.k1, sys.kc, 1.0, 0.0}, b{sys.m2, sys.k2, sys.kc, 0.0, 0.0};
  const int windows = static_cast<int>(std::lround(T / H));
  for (int w = 0; w < windows; ++w) {
    const double t0 = w * H;
    const Side a0 = a, b0 = b;  // the checkpoint each iteration restarts from
    Waveform xb(degree, 1);
    xb.add(t0, {b.x});  // first iteration: b held at its start
    for (int it = 0;; ++it) {
      if (it == 200) throw std::runtime_error("waveform iteration did not converge");
      a = a0;
      b = b0;
      const Waveform xa = a.advance(t0, H, substeps, xb, degree);
      const Waveform next = b.advance(t0, H, substeps, xa, degree);
      double change = 0;
      if (next.samples() == xb.samples())
        for (std::size_t i = 0; i < next.samples(); ++i)
          change = std::max(change, std::abs(next.sample(i)[0] - xb.sample(i)[0]));
      else
        change = INFINITY;
      xb = next;
      if (change < 1e-14) break;
    }
  }
  return std::abs(a.x - sys.x1_exact(T));
}

// Held (degree 0) samples are first order, linear second, quadratic third,
// cubic fourth (RK4's own order, which the substeps share), each within 0.3.
TEST(Waveform, EachDegreeGivesItsOrderOnTwoCoupledMasses) {
  const std::vector<double> H = {1.0 / 16, 1.0 / 32, 1.0 / 64, 1.0 / 128};
  for (int p = 0; p <= Waveform::kMaxDegree; ++p) {
    std::vector<double> err;
    for (double h : H) err.push_back(coupled_error(p, h, 1.0, 4));
    const double order = test::fitted_order(H, err);
    EXPECT_NEAR(order, p + 1.0, 0.3)
        << "degree " << p << ": errors " << err[0] << " ... " << err.back();
  }
}

}  // namespace
}  // namespace railcosim
