#include "verdict/spectrum.hpp"

#include "verdict/dense_eigen.hpp"

#include <Eigen/Core>
// GCC 12 reports a use after free inside Spectra's Hessenberg eigen-solver
// where Eigen frees a temporary it no longer reads (a false positive of
// its inlining); clang has no such warning.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuse-after-free"
#endif
#include <Spectra/GenEigsSolver.h>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

namespace railcosim::verdict {
namespace {

using Clock = std::chrono::steady_clock;

// Raised inside a product when the budget is spent; caught below.
struct OutOfBudget {
  std::string why;
};

// The operator as Spectra sees it, counting its products against the budget.
class CountedProduct {
 public:
  using Scalar = double;

  CountedProduct(const LinearOperator& a, const Budget& b) : a_(a), b_(b), t0_(Clock::now()) {}

  Eigen::Index rows() const { return a_.dimension; }
  Eigen::Index cols() const { return a_.dimension; }

  void perform_op(const double* x, double* y) const {
    if (b_.stop && b_.stop()) throw Stopped("stopped by a signal");
    if (b_.max_products > 0 && products_ >= b_.max_products) {
      std::ostringstream s;
      s << "its budget of " << b_.max_products << " products of the map was spent";
      throw OutOfBudget{s.str()};
    }
    if (b_.max_seconds > 0 && seconds() > b_.max_seconds) {
      std::ostringstream s;
      s << "its budget of " << b_.max_seconds << " s was spent after " << products_
        << " products of the map";
      throw OutOfBudget{s.str()};
    }
    ++products_;
    a_.apply(x, y);
  }

  long products() const { return products_; }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }

 private:
  const LinearOperator& a_;
  const Budget& b_;
  Clock::time_point t0_;
  mutable long products_ = 0;
};

void finish(Spectrum& s, const CountedProduct& op) {
  s.products = op.products();
  s.seconds = op.seconds();
}

// The eigenvalues largest first, and rho with its eigenvalue.
void take(Spectrum& s, const Eigen::VectorXcd& values) {
  s.leading.assign(values.data(), values.data() + values.size());
  std::stable_sort(s.leading.begin(), s.leading.end(),
                   [](auto a, auto b) { return std::abs(a) > std::abs(b); });
  if (!s.leading.empty()) {
    s.dominant = s.leading.front();
    s.rho = std::abs(s.dominant);
  }
  s.converged = true;
}

}  // namespace

Eigen::MatrixXd dense_matrix(const LinearOperator& a) {
  const auto N = static_cast<Eigen::Index>(a.dimension);
  Eigen::MatrixXd A(N, N);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(N);
  for (Eigen::Index j = 0; j < N; ++j) {
    e(j) = 1;
    a.apply(e.data(), A.col(j).data());
    e(j) = 0;
  }
  return A;
}

Eigen::MatrixXd without_zero_columns(const Eigen::MatrixXd& A) {
  std::vector<Eigen::Index> kept;
  for (Eigen::Index j = 0; j < A.cols(); ++j)
    if ((A.col(j).array() != 0).any()) kept.push_back(j);
  const auto K = static_cast<Eigen::Index>(kept.size());
  Eigen::MatrixXd R(K, K);
  for (Eigen::Index i = 0; i < K; ++i)
    for (Eigen::Index j = 0; j < K; ++j)
      R(i, j) = A(kept[static_cast<std::size_t>(i)], kept[static_cast<std::size_t>(j)]);
  return R;
}

Spectrum dense_spectrum(const LinearOperator& a, const Budget& budget) {
  Spectrum s;
  s.method = "dense";
  const CountedProduct op(a, budget);
  const auto N = static_cast<Eigen::Index>(a.dimension);
  try {
    Eigen::MatrixXd A(N, N);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(N);
    for (Eigen::Index j = 0; j < N; ++j) {
      e(j) = 1;
      op.perform_op(e.data(), A.col(j).data());
      e(j) = 0;
    }
    Eigen::MatrixXd R = without_zero_columns(A);
    const Eigen::Index K = R.rows();
    s.dimension = K;
    if (K > 0) {
      const double left =
          budget.max_seconds > 0 ? std::max(1e-3, budget.max_seconds - op.seconds()) : 0.0;
      bool stopped = false;
      auto eig = dense_eigenvalues(std::move(R), budget.stop, left, stopped);
      if (stopped) throw Stopped("stopped by a signal");
      s.solver = eig->solver;
      if (!eig->why_not.empty()) {
        s.why_not = eig->why_not;
        finish(s, op);
        return s;
      }
      take(s, eig->values);
    } else {
      s.converged = true;
    }
  } catch (const OutOfBudget& b) {
    s.why_not = b.why;
  }
  finish(s, op);
  return s;
}

Spectrum dominant_spectrum(const LinearOperator& a, const Budget& budget, const KrylovSettings& k) {
  const long n = a.dimension;
  // Arnoldi needs a subspace of at least nev + 2 < n: a smaller map is
  // taken whole.
  const long nev = std::min<long>(k.eigenvalues, std::max<long>(1, n - 3));
  const long ncv = std::min<long>(std::max<long>(k.subspace, nev + 2), n);
  if (n < 4 || ncv >= n || ncv < nev + 2) {
    Spectrum s = dense_spectrum(a, budget);
    return s;
  }
  Spectrum s;
  s.method = "krylov";
  s.solver = "Spectra GenEigsSolver";
  s.dimension = n;
  CountedProduct op(a, budget);
  try {
    Spectra::GenEigsSolver<CountedProduct> eigs(op, static_cast<Eigen::Index>(nev),
                                                static_cast<Eigen::Index>(ncv));
    std::mt19937_64 gen(k.seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd start(n);
    for (Eigen::Index i = 0; i < start.size(); ++i) start(i) = u(gen);
    eigs.init(start.data());
    // The restarts are bounded by the budget's products; without one, by
    // a thousand restarts.
    const Eigen::Index restarts = 1000;
    eigs.compute(Spectra::SortRule::LargestMagn, restarts, k.tolerance);
    s.restarts = static_cast<long>(eigs.num_iterations());
    if (eigs.info() == Spectra::CompInfo::Successful) {
      take(s, eigs.eigenvalues());
    } else {
      std::ostringstream w;
      w << "the Arnoldi iteration did not converge in " << s.restarts << " restarts";
      s.why_not = w.str();
    }
  } catch (const OutOfBudget& b) {
    s.why_not = "the Arnoldi iteration did not converge before " + b.why;
  }
  finish(s, op);
  return s;
}

}  // namespace railcosim::verdict
