// The dominant eigenvalues of a linear map seen only through its product:
// the map's contract with the verdict (the others: matrix_free.hpp's
// passes, reference.hpp's maker of reference runs). Whatever the map is
// (one macro step of a co-simulation linearised at rest, built-in
// participants, an SDK's or an FMU's), the measure sees a dimension and
// y = A x.
//
// dominant_spectrum() is Arnoldi's method with implicit restarts (Spectra's
// GenEigsSolver on Eigen), asking for the eigenvalues of largest modulus:
// its cost is a number of products and O(N k) memory, not the N products
// and O(N^3) work of the whole matrix. dense_spectrum() builds every column
// and computes every eigenvalue (Eigen's real Schur form): exact, the
// oracle of the tests and the measure of small maps.
//
// Both are bounded: a budget of products and of seconds, and a stop that is
// asked before every product. A measure that does not converge within its
// budget says so (Spectrum::converged false, why_not) and never returns a
// radius it has not converged to.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace railcosim::verdict {

struct LinearOperator {
  long dimension = 0;
  // y = A x, both of `dimension` values.
  std::function<void(const double* x, double* y)> apply;
};

struct Budget {
  long max_products = 0;   // 0: no bound
  double max_seconds = 0;  // 0: no bound
  // Asked before every product; true ends the measure with Stopped.
  std::function<bool()> stop;
};

// Thrown through the measure when Budget::stop says so.
class Stopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct KrylovSettings {
  int eigenvalues = 2;  // converged eigenvalues asked for (the largest in modulus)
  int subspace = 40;    // the Krylov subspace's dimension at each restart
  // Spectra's relative bound on a Ritz pair's residual.
  double tolerance = 1e-8;
  // The first vector, from this seed (a fixed seed: the same answer every run).
  unsigned seed = 20261202;
};

struct Spectrum {
  bool converged = false;
  double rho = 0;                             // the largest modulus among the converged eigenvalues
  std::complex<double> dominant;              // the eigenvalue of that modulus
  std::vector<std::complex<double>> leading;  // the converged eigenvalues, largest first
  long products = 0;                          // products y = A x taken
  long restarts = 0;                          // Arnoldi restarts
  double seconds = 0;                         // wall time
  long dimension = 0;  // the map's dimension (dense: after dropping zero columns)
  std::string method;  // "krylov" or "dense"
  std::string solver;  // dense: the eigen-solver (dense_eigen.hpp); krylov: "Spectra GenEigsSolver"
  std::string why_not;  // when not converged: why
};

Spectrum dominant_spectrum(const LinearOperator& a, const Budget& budget,
                           const KrylovSettings& settings = {});

// The matrix of the map: every column A e_j (no budget, no stop).
Eigen::MatrixXd dense_matrix(const LinearOperator& a);
// A less its zero columns and their rows (the eigenvalues dropped are 0):
// what the dense measure solves.
Eigen::MatrixXd without_zero_columns(const Eigen::MatrixXd& A);

// Every column A e_j; columns that are zero are dropped with their rows
// (their eigenvalues are 0).
Spectrum dense_spectrum(const LinearOperator& a, const Budget& budget = {});

}  // namespace railcosim::verdict
