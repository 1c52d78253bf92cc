#include "beam_element.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "test_support.hpp"

namespace railcosim {
namespace {

// The paper's rail element.
constexpr double kEI = 210e9 * 1987e-8;
constexpr double kRhoA = 7850.0 * 63.8e-4;
constexpr double kL = 0.3;

TEST(BeamElement, MatricesAreSymmetric) {
  const Matrix4 k = beam_stiffness(kEI, kL), m = beam_consistent_mass(kRhoA, kL);
  EXPECT_TRUE(test::matrices_near(k, k.transpose(), 0.0));
  EXPECT_TRUE(test::matrices_near(m, m.transpose(), 0.0));
}

TEST(BeamElement, FreeStiffnessHasExactlyTwoRigidModes) {
  const Matrix4 k = beam_stiffness(kEI, kL);
  Eigen::SelfAdjointEigenSolver<Matrix4> eig(k);
  const Vector4 ev = eig.eigenvalues();  // ascending
  // Zero relative to the largest eigenvalue, up to round-off.
  const double zero = 1e-12 * ev[3];
  EXPECT_LT(std::abs(ev[0]), zero);
  EXPECT_LT(std::abs(ev[1]), zero);
  EXPECT_GT(ev[2], 1e-3 * ev[3]);
  // The two modes are rigid translation and rotation: K times each is zero.
  const Vector4 translation(1, 0, 1, 0), rotation(-kL / 2, 1, kL / 2, 1);
  EXPECT_LT((k * translation).norm(), zero);
  EXPECT_LT((k * rotation).norm(), zero);
}

TEST(BeamElement, MassMatrixCarriesTheElementMass) {
  const Matrix4 m = beam_consistent_mass(kRhoA, kL);
  const Vector4 translation(1, 0, 1, 0);
  EXPECT_NEAR(translation.dot(m * translation), kRhoA * kL, 1e-12 * kRhoA * kL);
  Eigen::SelfAdjointEigenSolver<Matrix4> eig(m);
  EXPECT_GT(eig.eigenvalues()[0], 0.0);  // positive definite
}

TEST(BeamElement, HermiteShapeInterpolatesNodesAndCubics) {
  EXPECT_TRUE(test::matrices_near(hermite_shape(0.0, kL), Vector4(1, 0, 0, 0), 0.0));
  EXPECT_TRUE(test::matrices_near(hermite_shape(1.0, kL), Vector4(0, 0, 1, 0), 1e-15));
  // Reproduces w(x) = x^3 exactly: nodal values (0, 0, L^3, 3 L^2).
  const Vector4 q(0, 0, kL * kL * kL, 3 * kL * kL);
  for (double xi : {0.1, 0.37, 0.5, 0.9}) {
    const double x = xi * kL;
    EXPECT_NEAR(hermite_shape(xi, kL).dot(q), x * x * x, 1e-15);
  }
}

}  // namespace
}  // namespace railcosim
