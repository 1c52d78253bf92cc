// The verdict's measures on maps whose eigenvalues are known in closed form
// (verdict/spectrum.hpp): Arnoldi's dominant eigenvalues against the exact
// ones, on a spectrum as crowded near the unit circle as a lightly damped
// track's; its budget and its stop.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <complex>
#include <random>

#include <Eigen/Dense>

#include "verdict/dense_eigen.hpp"
#include "verdict/spectrum.hpp"

namespace railcosim::verdict_spectrum_test {
namespace {

// A real matrix Q^T B Q: B block-diagonal with rotation blocks of moduli
// r_k and angles phi_k (eigenvalues r_k e^{+-i phi_k}), Q orthogonal.
struct Known {
  Eigen::MatrixXd A;
  double rho = 0;
};

Known crowded(int pairs, double top, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 2 * pairs;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, n);
  Known k;
  for (int p = 0; p < pairs; ++p) {
    // Moduli from 1 - 1e-3 up to just below 1, the largest `top`.
    const double r = p == 0 ? top : 1 - 1e-3 * u(gen) - 1e-7;
    const double phi = M_PI * u(gen);
    B(2 * p, 2 * p) = r * std::cos(phi);
    B(2 * p, 2 * p + 1) = -r * std::sin(phi);
    B(2 * p + 1, 2 * p) = r * std::sin(phi);
    B(2 * p + 1, 2 * p + 1) = r * std::cos(phi);
    k.rho = std::max(k.rho, r);
  }
  Eigen::MatrixXd G(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) G(i, j) = u(gen) - 0.5;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
  const Eigen::MatrixXd Q = qr.householderQ();
  k.A = Q.transpose() * B * Q;
  return k;
}

verdict::LinearOperator product_of(const Eigen::MatrixXd& A) {
  verdict::LinearOperator op;
  op.dimension = A.rows();
  op.apply = [&A](const double* x, double* y) {
    Eigen::Map<Eigen::VectorXd>(y, A.rows()) = A * Eigen::Map<const Eigen::VectorXd>(x, A.cols());
  };
  return op;
}

// A dominant eigenvalue well outside the rest (an unstable coupling's mode
// over a ring of lightly damped ones): Arnoldi finds it exactly, in far
// fewer products than the dense map's columns.
TEST(VerdictSpectrum, ArnoldiFindsAnIsolatedDominantEigenvalue) {
  for (double top : {1.055, 6.2}) {
    const Known k = crowded(400, top, 7);
    const verdict::Spectrum s = verdict::dominant_spectrum(product_of(k.A), {});
    ASSERT_TRUE(s.converged) << s.why_not;
    EXPECT_EQ(s.method, "krylov");
    EXPECT_NEAR(s.rho, k.rho, 1e-9 * k.rho) << "top " << top;
    EXPECT_LT(s.products, 800) << "top " << top;
    const verdict::Spectrum d = verdict::dense_spectrum(product_of(k.A));
    ASSERT_TRUE(d.converged);
    EXPECT_EQ(d.products, 800);
    EXPECT_NEAR(d.rho, k.rho, 1e-12 * k.rho);
  }
}

// A spectrum crowded along the unit circle (moduli 1e-7 to 1e-3 below 1 at
// every angle): Arnoldi's converged eigenvalues are eigenvalues, but not
// necessarily the largest. It may say converged with a smaller rho, never
// a larger one: a "stable" from it proves nothing, an "unstable" does.
TEST(VerdictSpectrum, OnACrowdedSpectrumArnoldiNeverOverstatesRho) {
  for (double top : {1.0000229, 0.99999972}) {
    const Known k = crowded(150, top, 7);
    verdict::Budget b;
    b.max_products = 3000;
    const verdict::Spectrum s = verdict::dominant_spectrum(product_of(k.A), b);
    if (s.converged) {
      EXPECT_LE(s.rho, k.rho + 1e-9) << "top " << top;
    } else {
      EXPECT_FALSE(s.why_not.empty());
    }
    const verdict::Spectrum d = verdict::dense_spectrum(product_of(k.A));
    EXPECT_NEAR(d.rho, k.rho, 1e-12);
  }
}

TEST(VerdictSpectrum, TheDenseOracleDropsColumnsTheMapIgnores) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4, 4);
  A(0, 0) = 0.5;
  A(1, 1) = -2.0;  // columns 2 and 3 are zero
  A(1, 2) = 7;     // (a zero column's row may hold anything: it is dropped too)
  A(1, 2) = 0;
  const verdict::Spectrum d = verdict::dense_spectrum(product_of(A));
  ASSERT_TRUE(d.converged);
  EXPECT_EQ(d.dimension, 2);
  EXPECT_DOUBLE_EQ(d.rho, 2.0);
  EXPECT_DOUBLE_EQ(d.dominant.real(), -2.0);
}

TEST(VerdictSpectrum, AMeasureOutOfItsBudgetIsNotConvergedAndSaysWhy) {
  const Known k = crowded(150, 1.0000229, 11);
  verdict::Budget b;
  b.max_products = 20;
  const verdict::Spectrum s = verdict::dominant_spectrum(product_of(k.A), b);
  EXPECT_FALSE(s.converged);
  EXPECT_EQ(s.rho, 0);
  EXPECT_EQ(s.products, 20);
  EXPECT_NE(s.why_not.find("budget of 20 products"), std::string::npos) << s.why_not;
  const verdict::Spectrum d = verdict::dense_spectrum(product_of(k.A), b);
  EXPECT_FALSE(d.converged);
  EXPECT_NE(d.why_not.find("budget of 20 products"), std::string::npos) << d.why_not;
}

TEST(VerdictSpectrum, TheStopEndsTheMeasureAtTheNextProduct) {
  const Known k = crowded(150, 1.0000229, 13);
  long asked = 0;
  verdict::Budget b;
  b.stop = [&asked] { return ++asked > 5; };
  EXPECT_THROW(verdict::dominant_spectrum(product_of(k.A), b), verdict::Stopped);
  EXPECT_EQ(asked, 6);
}

TEST(VerdictSpectrum, ASmallMapIsTakenWhole) {
  Eigen::MatrixXd A(3, 3);
  A << 0.9, 1, 0, 0, 0.9, 1, 0, 0, 0.5;
  const verdict::Spectrum s = verdict::dominant_spectrum(product_of(A), {});
  ASSERT_TRUE(s.converged);
  EXPECT_EQ(s.method, "dense");
  EXPECT_NEAR(s.rho, 0.9, 1e-7);
}

// The dense measure's eigenvalues are the closed form's: every one of a
// crowded spectrum, not only the largest, by the solver the size chooses
// (Eigen's below kLapackFrom coordinates, LAPACK's above) and by each of
// the two by name.
TEST(VerdictSpectrum, TheDenseEigenvaluesAreTheClosedFormsEveryOne) {
  for (const int pairs : {200, 600}) {
    const Known k = crowded(pairs, 1.0000229, 17);
    const verdict::Spectrum d = verdict::dense_spectrum(product_of(k.A));
    ASSERT_TRUE(d.converged) << d.why_not;
    ASSERT_EQ(d.leading.size(), static_cast<std::size_t>(2 * pairs));
    EXPECT_NEAR(d.rho, k.rho, 1e-12) << pairs;
    // The moduli come in conjugate pairs, each pair one rotation block's.
    for (std::size_t i = 0; i + 1 < d.leading.size(); i += 2)
      EXPECT_NEAR(std::abs(d.leading[i]), std::abs(d.leading[i + 1]), 1e-12) << pairs << " " << i;
    const bool lapack = 2 * pairs >= verdict::kLapackFrom;
    EXPECT_EQ(d.solver, lapack ? "LAPACK dgeev (" + verdict::lapack_library() + ")"
                               : std::string("Eigen EigenSolver"));
    for (const auto solver : {verdict::DenseSolver::kEigen, verdict::DenseSolver::kLapack}) {
      bool stopped = false;
      const auto e = verdict::dense_eigenvalues(k.A, {}, 0, stopped, solver);
      ASSERT_TRUE(e.has_value());
      ASSERT_TRUE(e->why_not.empty()) << e->why_not;
      ASSERT_EQ(e->values.size(), 2 * pairs);
      EXPECT_NEAR(e->values.cwiseAbs().maxCoeff(), k.rho, 1e-12) << e->solver;
    }
  }
}

// A large matrix's eigenvalues take seconds: the stop and the time budget
// end the wait within a fraction of a second, the stop by Stopped and the
// budget with the reason.
TEST(VerdictSpectrum, TheStopAndTheBudgetEndTheDenseEigenvaluesWithinASecond) {
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 1600;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = u(gen);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  bool stopped = false;
  const auto stop_after = [t0] {
    return std::chrono::duration<double>(Clock::now() - t0).count() > 0.2;
  };
  EXPECT_FALSE(verdict::dense_eigenvalues(A, stop_after, 0, stopped).has_value());
  EXPECT_TRUE(stopped);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 1.0);
  const auto t1 = Clock::now();
  const auto late = verdict::dense_eigenvalues(A, {}, 0.2, stopped);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t1).count(), 1.0);
  ASSERT_TRUE(late.has_value());
  EXPECT_FALSE(stopped);
  EXPECT_NE(late->why_not.find("budget of 0.2 s"), std::string::npos) << late->why_not;
}

}  // namespace
}  // namespace railcosim::verdict_spectrum_test
