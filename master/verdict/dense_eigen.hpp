// Every eigenvalue of a dense real matrix, by one of two solvers: LAPACK's
// multishift QR (dgeev without eigenvectors: balancing, Hessenberg
// reduction, the Hessenberg QR iteration with aggressive early deflation)
// or Eigen's double-shift QR (EigenSolver without eigenvectors). Which one
// depends on the LAPACK the program runs with: OpenBLAS's (what
// scripts/install-deps.sh installs) is faster than Eigen's solver at every
// size of the verdict's maps (1.3 to 3.6 times from 507 to 1,406
// coordinates), and is taken at every size; the reference LAPACK breaks even
// with Eigen's solver near kLapackFrom coordinates, and is taken from there
// on (bench/dense_eigen_bench.cpp; docs/benchmarks.md, "The verdict's
// cost").
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
// The size from which the default solver is LAPACK's: 0 with OpenBLAS,
// kLapackFrom with the reference LAPACK.
long lapack_from();

struct DenseEigenvalues {
  Eigen::VectorXcd values;
  std::string why_not;  // empty when the iteration converged
  std::string solver;   // "LAPACK dgeev (<library>)" or "Eigen EigenSolver"
};

// Which solver: by size (lapack_from()), or one of the two (the tests' and
// the benchmark's).
enum class DenseSolver { kBySize, kEigen, kLapack };

// Returns nothing when `stop` said so (the caller then throws Stopped), or
// when `give_up_after` seconds (> 0) passed (why_not says so).
std::optional<DenseEigenvalues> dense_eigenvalues(Eigen::MatrixXd matrix,
                                                  const std::function<bool()>& stop,
                                                  double give_up_after, bool& stopped,
                                                  DenseSolver solver = DenseSolver::kBySize);

}  // namespace railcosim::verdict
