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

}  // namespace railcosim::test
