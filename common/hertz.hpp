// Hertz wheel/rail contact law: F = K_H * max(delta, 0)^(3/2), no tension.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace railcosim {

inline double hertz_force(double K_H, double delta) {
  return delta > 0.0 ? K_H * delta * std::sqrt(delta) : 0.0;
}

// The penetration that carries a compressive force F >= 0.
inline double hertz_penetration(double K_H, double F) {
  return std::cbrt((F / K_H) * (F / K_H));
}

// Solves delta = d0 - c * F(delta) for delta, with c >= 0: the penetration
// left once an elastic system of flexibility c has yielded under the contact
// force. phi(delta) = delta + c K_H delta^1.5 - d0 is increasing and convex,
// so Newton's method started right of the root converges monotonically.
inline double hertz_solve_penetration(double K_H, double d0, double c) {
  if (d0 <= 0.0 || c == 0.0) return d0;
  double delta = d0;
  if (c * K_H * std::sqrt(d0) > 1.0) {
    // Stiff system: start from the root of c K_H delta^1.5 = d0, still right
    // of the true root, so the iteration stays monotone and converges fast.
    delta = std::cbrt((d0 / (c * K_H)) * (d0 / (c * K_H)));
  }
  for (int it = 0; it < 100; ++it) {
    const double s = std::sqrt(delta);
    const double phi = delta + c * K_H * delta * s - d0;
    const double dphi = 1.0 + 1.5 * c * K_H * s;
    const double next = delta - phi / dphi;
    if (!(next < delta)) break;  // monotone descent has stalled: converged
    delta = next;
  }
  return delta;
}

// Several contacts on one elastic system: delta_j = d0_j - sum_k c_jk F(delta_k)
// with the symmetric flexibility c (c_jk: the penetration of contact j under a
// unit force at contact k). Nonlinear Gauss-Seidel over the contacts, each
// solved exactly by hertz_solve_penetration for the others' forces: the
// wheels of a vehicle stand metres apart, so c is strongly diagonally
// dominant and a few sweeps reach round-off. Returns the forces, or an empty
// vector if the sweeps did not settle (a flexibility that couples the
// contacts more strongly than they are held).
template <class Matrix>
std::vector<double> hertz_solve_coupled(double K_H, const std::vector<double>& d0,
                                        const Matrix& c) {
  const std::size_t n = d0.size();
  std::vector<double> F(n, 0.0);
  for (int sweep = 0; sweep < 200; ++sweep) {
    double change = 0, largest = 0;
    for (std::size_t k = 0; k < n; ++k) {
      double d = d0[k];
      for (std::size_t j = 0; j < n; ++j)
        if (j != k) d -= c(k, j) * F[j];
      const double f = hertz_force(K_H, hertz_solve_penetration(K_H, d, c(k, k)));
      change = std::max(change, std::abs(f - F[k]));
      largest = std::max(largest, std::abs(f));
      F[k] = f;
    }
    // A force settled to a few ulps of the largest one is converged.
    if (change <= 1e-14 * largest) return F;
  }
  return {};
}

}  // namespace railcosim
