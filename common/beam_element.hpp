// Euler–Bernoulli beam element with cubic Hermite interpolation.
//
// Local DOF order: (w_1, theta_1, w_2, theta_2), w positive downward and
// theta = dw/dx. These are the standard two-node bending element matrices.
#pragma once

#include <Eigen/Core>

namespace railcosim {

using Matrix4 = Eigen::Matrix4d;
using Vector4 = Eigen::Vector4d;

// Bending stiffness EI/L^3 [12 6L -12 6L; 6L 4L^2 -6L 2L^2; ...].
Matrix4 beam_stiffness(double EI, double L);

// Consistent mass rho*A*L/420 [156 22L 54 -13L; ...].
Matrix4 beam_consistent_mass(double rhoA, double L);

// Hermite shape functions at local coordinate xi = s/L in [0, 1]:
// w(s) = N(xi) . (w_1, theta_1, w_2, theta_2).
Vector4 hermite_shape(double xi, double L);

}  // namespace railcosim
