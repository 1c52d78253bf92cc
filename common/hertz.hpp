// Hertz wheel/rail contact law: F = K_H * max(delta, 0)^(3/2), no tension.
#pragma once

#include <cmath>

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

}  // namespace railcosim
