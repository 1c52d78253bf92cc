// Helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "scene.hpp"

namespace railcosim::test {

inline std::string source_path(const std::string& relative) {
  return std::string(RAILCOSIM_SOURCE_DIR) + "/" + relative;
}

inline Scene paper_scene() {
  return load_scene(source_path("scenes/paper.toml"));
}

// Compares two Eigen objects entry by entry and prints both on failure.
inline ::testing::AssertionResult matrices_near(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                                                double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << "shapes differ";
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "max |a - b| = " << diff << " > " << tol << "\na =\n"
                                       << a << "\nb =\n"
                                       << b;
}

// Least-squares slope of log(err) against log(h).
inline double fitted_order(const std::vector<double>& h, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// One classical Runge-Kutta step of x'' = acc(t, x) from (x, v) at t over h.
template <class Acc>
void rk4_step(double& x, double& v, double t, double h, Acc acc) {
  const double k1x = v, k1v = acc(t, x);
  const double k2x = v + 0.5 * h * k1v, k2v = acc(t + 0.5 * h, x + 0.5 * h * k1x);
  const double k3x = v + 0.5 * h * k2v, k3v = acc(t + 0.5 * h, x + 0.5 * h * k2x);
  const double k4x = v + h * k3v, k4v = acc(t + h, x + h * k3x);
  x += h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
  v += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

}  // namespace railcosim::test
