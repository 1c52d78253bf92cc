// Every eigenvalue of a dense real matrix. From kLapackFrom coordinates by
// LAPACK's multishift QR (dgeev without eigenvectors: balancing, Hessenberg
// reduction, the Hessenberg QR iteration with aggressive early deflation),
// below by Eigen's double-shift QR (EigenSolver without eigenvectors): on
// the verdict's own maps the two break even near 1,000 coordinates with the
// reference LAPACK (bench/dense_eigen_bench.cpp; docs/benchmarks.md, "The
// verdict's cost"). OpenBLAS's LAPACK is faster at every size, but its
// eigenvalues of the same map differ between processes (1e-11 in rho), so
// the size alone decides, and the solver's name says which LAPACK ran.
//
// The iteration runs on a thread of its own so that the caller can still
// keep its promise to stop within a second: the wait asks `stop` every
// 50 ms and gives up, leaving the iteration to finish on data it owns.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>

namespace railcosim::verdict {

inline constexpr long kLapackFrom = 1000;

// The LAPACK this program runs with: "OpenBLAS" or "reference" (any other).
std::string lapack_library();

struct DenseEigenvalues {
  Eigen::VectorXcd values;
  std::string why_not;  // empty when the iteration converged
  std::string solver;   // "LAPACK dgeev (<library>)" or "Eigen EigenSolver"
};

// Which solver: by size (kLapackFrom), or one of the two (the tests' and
// the benchmark's).
enum class DenseSolver { kBySize, kEigen, kLapack };

// Returns nothing when `stop` said so (the caller then throws Stopped), or
// when `give_up_after` seconds (> 0) passed (why_not says so).
std::optional<DenseEigenvalues> dense_eigenvalues(Eigen::MatrixXd matrix,
                                                  const std::function<bool()>& stop,
                                                  double give_up_after, bool& stopped,
                                                  DenseSolver solver = DenseSolver::kBySize);

}  // namespace railcosim::verdict
