#include "banded_matrix.hpp"

#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

namespace railcosim {
namespace {

// Round-off bound for products and solves of well-conditioned 40x40 systems.
constexpr double kRoundOff = 1e-12;

SymmetricBandMatrix random_spd(int n, int kd, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SymmetricBandMatrix A(n, kd);
  for (int j = 0; j < n; ++j) {
    A.add(j, j, 4.0 * kd + 1.0);  // diagonally dominant: positive definite
    for (int d = 1; d <= kd && j + d < n; ++d) A.add(j + d, j, u(rng));
  }
  return A;
}

class BandedMatrixTest : public ::testing::TestWithParam<int> {};

TEST_P(BandedMatrixTest, ProductMatchesDense) {
  const int kd = GetParam();
  const SymmetricBandMatrix A = random_spd(40, kd, 7);
  const Vector x = Vector::LinSpaced(40, -1.0, 2.0);
  Vector y;
  A.multiply(x, y);
  EXPECT_TRUE(test::matrices_near(y, A.to_dense() * x, kRoundOff));
}

TEST_P(BandedMatrixTest, FusedProductMatchesDense) {
  const int kd = GetParam();
  const SymmetricBandMatrix A = random_spd(40, kd, 1), B = random_spd(40, kd, 2);
  const Vector x = Vector::LinSpaced(40, -1.0, 2.0), z = Vector::LinSpaced(40, 3.0, -2.0);
  Vector y = Vector::Ones(40);
  SymmetricBandMatrix::multiply_add2(0.5, A, x, -2.0, B, z, y);
  const Vector expected = Vector::Ones(40) + 0.5 * A.to_dense() * x - 2.0 * B.to_dense() * z;
  EXPECT_TRUE(test::matrices_near(y, expected, kRoundOff));
}

// The fused product skips the band's empty entries (a mass or damping matrix
// is mostly empty): a band with holes, and a matrix changed after a product
// (the cached nonzeros must follow), against the dense product.
TEST_P(BandedMatrixTest, FusedProductOfASparseBandFollowsChanges) {
  const int kd = GetParam();
  SymmetricBandMatrix A(40, kd), B = random_spd(40, kd, 4);
  for (int j = 0; j < 40; j += 3) A.add(j, j, 1.0 + j);
  if (kd > 0)
    for (int j = 0; j + kd < 40; j += 5) A.add(j + kd, j, -0.5);
  const Vector x = Vector::LinSpaced(40, -1.0, 2.0), z = Vector::LinSpaced(40, 3.0, -2.0);
  Vector y = Vector::Zero(40);
  SymmetricBandMatrix::multiply_add2(1.5, A, x, 0.25, B, z, y);
  EXPECT_TRUE(test::matrices_near(y, 1.5 * A.to_dense() * x + 0.25 * B.to_dense() * z, kRoundOff));
  A.add(1, 1, 7.0);  // a new nonzero where the band was empty
  y.setZero();
  SymmetricBandMatrix::multiply_add2(1.5, A, x, 0.25, B, z, y);
  EXPECT_TRUE(test::matrices_near(y, 1.5 * A.to_dense() * x + 0.25 * B.to_dense() * z, kRoundOff));
}

TEST_P(BandedMatrixTest, CholeskySolveMatchesDense) {
  const int kd = GetParam();
  const SymmetricBandMatrix A = random_spd(40, kd, 3);
  Vector b = Vector::LinSpaced(40, 1.0, -1.0);
  const Vector expected = A.to_dense().ldlt().solve(b);
  BandCholesky(A).solve_in_place(b);
  EXPECT_TRUE(test::matrices_near(b, expected, kRoundOff));
}

// 0 and 4 take the unrolled kernels, 6 the generic ones.
INSTANTIATE_TEST_SUITE_P(Bandwidths, BandedMatrixTest, ::testing::Values(0, 1, 4, 6));

TEST(BandCholesky, RejectsIndefiniteMatrix) {
  SymmetricBandMatrix A(3, 1);
  A.add(0, 0, 1.0);
  A.add(1, 1, -1.0);
  A.add(2, 2, 1.0);
  EXPECT_THROW(BandCholesky{A}, std::runtime_error);
}

}  // namespace
}  // namespace railcosim
