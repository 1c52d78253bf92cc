#include "verdict/dense_eigen.hpp"

#include <Eigen/Eigenvalues>

#include <dlfcn.h>

#include <chrono>
#include <cstddef>
#include <future>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

// LAPACK's Fortran entry point, with the lengths of its two character
// arguments that gfortran passes after the others.
extern "C" void dgeev_(const char* jobvl, const char* jobvr, const int* n, double* a,
                       const int* lda, double* wr, double* wi, double* vl, const int* ldvl,
                       double* vr, const int* ldvr, double* work, const int* lwork, int* info,
                       std::size_t jobvl_len, std::size_t jobvr_len);

namespace railcosim::verdict {

std::string lapack_library() {
  // OpenBLAS's own entry point is in the process when the LAPACK (and BLAS)
  // the dynamic linker chose is OpenBLAS's (Debian's alternatives decide).
  static const bool openblas = dlsym(RTLD_DEFAULT, "openblas_get_config") != nullptr;
  return openblas ? "OpenBLAS" : "reference";
}

namespace {

DenseEigenvalues solve_eigen(const Eigen::MatrixXd& a) {
  DenseEigenvalues out;
  out.solver = "Eigen EigenSolver";
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a, false);
  if (eig.info() != Eigen::Success)
    out.why_not = "the eigenvalue iteration of the map's matrix did not converge";
  else
    out.values = eig.eigenvalues();
  return out;
}

DenseEigenvalues solve_lapack(Eigen::MatrixXd& a) {
  DenseEigenvalues out;
  out.solver = "LAPACK dgeev (" + lapack_library() + ")";
  const int n = static_cast<int>(a.rows());
  const int one = 1;
  std::vector<double> wr(static_cast<std::size_t>(n)), wi(static_cast<std::size_t>(n));
  double query = 0;
  int lwork = -1, info = 0;
  dgeev_("N", "N", &n, a.data(), &n, wr.data(), wi.data(), nullptr, &one, nullptr, &one, &query,
         &lwork, &info, 1, 1);
  lwork = static_cast<int>(query);
  std::vector<double> work(static_cast<std::size_t>(std::max(lwork, 1)));
  dgeev_("N", "N", &n, a.data(), &n, wr.data(), wi.data(), nullptr, &one, nullptr, &one,
         work.data(), &lwork, &info, 1, 1);
  if (info != 0) {
    std::ostringstream s;
    s << "the QR iteration of the map's matrix did not converge (LAPACK dgeev info " << info << ")";
    out.why_not = s.str();
    return out;
  }
  out.values.resize(n);
  for (int i = 0; i < n; ++i)
    out.values(i) = {wr[static_cast<std::size_t>(i)], wi[static_cast<std::size_t>(i)]};
  return out;
}

DenseEigenvalues solve(Eigen::MatrixXd& a, DenseSolver solver) {
  const bool lapack =
      solver == DenseSolver::kLapack || (solver == DenseSolver::kBySize && a.rows() >= kLapackFrom);
  return lapack ? solve_lapack(a) : solve_eigen(a);
}

}  // namespace

std::optional<DenseEigenvalues> dense_eigenvalues(Eigen::MatrixXd matrix,
                                                  const std::function<bool()>& stop,
                                                  double give_up_after, bool& stopped,
                                                  DenseSolver solver) {
  stopped = false;
  // The thread owns the matrix and the promise: a wait that gives up leaves
  // nothing behind that the thread still reads.
  auto owned = std::make_shared<Eigen::MatrixXd>(std::move(matrix));
  auto promise = std::make_shared<std::promise<DenseEigenvalues>>();
  std::future<DenseEigenvalues> result = promise->get_future();
  std::thread([owned, promise, solver] { promise->set_value(solve(*owned, solver)); }).detach();
  const auto t0 = std::chrono::steady_clock::now();
  while (result.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
    if (stop && stop()) {
      stopped = true;
      return std::nullopt;
    }
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (give_up_after > 0 && waited > give_up_after) {
      DenseEigenvalues late;
      std::ostringstream s;
      s << "its budget of " << give_up_after << " s was spent in the eigenvalues of the "
        << owned->rows() << " x " << owned->rows() << " matrix";
      late.why_not = s.str();
      return late;
    }
  }
  return result.get();
}

}  // namespace railcosim::verdict
