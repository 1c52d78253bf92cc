// The dense measure's eigen-solve on the maps it takes whole, by the solver
// the verdict uses (LAPACK's multishift QR with aggressive early deflation,
// verdict/dense_eigen.hpp) against the double-shift QR without deflation of
// Eigen's EigenSolver (the verdict's solver until 2026-12), on the same
// matrix in the same run: the paper scene's maps and the 155-sleeper one.
// Each line prints both times, their ratio and the two spectral radii.
#include <Eigen/Eigenvalues>
#include <chrono>
#include <cstdio>
#include <string>

#include "cosim_case.hpp"
#include "run/spectral.hpp"
#include "scene.hpp"
#include "verdict/dense_eigen.hpp"
#include "verdict/spectrum.hpp"

namespace railcosim {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void compare(const char* file, const char* name, int sleepers, double H) {
  Scene scene = load_scene(std::string(RAILCOSIM_SOURCE_DIR) + "/scenes/" + file);
  if (sleepers > 0) scene.sleeper_count = sleepers;
  scene.validate();
  run::RunOptions o;
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  const Eigen::MatrixXd R =
      verdict::without_zero_columns(run::macro_step_matrix(scene, parse_case(name), o));
  auto t0 = Clock::now();
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(R, false);
  const double eigen_s = seconds_since(t0);
  t0 = Clock::now();
  bool stopped = false;
  const auto lapack = verdict::dense_eigenvalues(R, {}, 0, stopped, verdict::DenseSolver::kLapack);
  const double lapack_s = seconds_since(t0);
  const double rho_eigen = eig.eigenvalues().cwiseAbs().maxCoeff();
  const double rho_lapack = lapack->values.cwiseAbs().maxCoeff();
  std::printf(
      "%-20s %4d sleepers H %-7g N %5ld  Eigen %8.3f s  LAPACK %8.3f s  ratio %5.2f  "
      "rho %.12f %.12f (diff %.1e)\n",
      name, scene.sleeper_count, H, static_cast<long>(R.rows()), eigen_s, lapack_s,
      eigen_s / lapack_s, rho_eigen, rho_lapack, rho_lapack - rho_eigen);
  std::fflush(stdout);
}

}  // namespace
}  // namespace railcosim

int main(int argc, char** argv) {
  using railcosim::compare;
  compare("paper.toml", "rs-xt-jacobi", 0, 1e-4);
  compare("paper.toml", "rs-xx-jacobi", 0, 1e-4);
  compare("paper.toml", "wr-xt-jacobi", 0, 1e-4);
  compare("paper.toml", "wr-xx-gauss-seidel", 0, 5e-4);
  compare("soil.toml", "ss-xt-jacobi", 0, 1e-4);
  compare("soil.toml", "wr-xt+ss-xx-jacobi", 0, 1e-4);
  compare("paper.toml", "rs-xx-jacobi", 80, 1e-4);
  compare("paper.toml", "rs-xx-jacobi", 100, 1e-4);
  // The 155-sleeper map (2,954 coordinates) costs minutes with Eigen: only
  // with --large.
  if (argc > 1 && std::string(argv[1]) == "--large")
    compare("paper.toml", "rs-xx-jacobi", 155, 1e-4);
  return 0;
}
