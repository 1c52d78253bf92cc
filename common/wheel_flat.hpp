// A wheel flat: a chord of length L cut into a wheel of diameter D. Rolling
// over it, the wheel's centre comes closer to the rail by the flat's radial
// depth f(s) at the contact point, s the distance rolled since t = 0, once
// per revolution (every pi D). It enters the contact as a reduction of the
// penetration:
//
//   delta = q - w_c - r(x_c) - f(s)
//
// Shapes (psi the angle of the contact point from the flat's centre, R = D/2,
// alpha = asin(L / D) the flat's half-angle):
//   chord   the exact chord: f = R - R cos(alpha) / cos(psi) for |psi| <= alpha;
//           its depth is d = R - sqrt(R^2 - L^2/4) (= L^2 / (4 D) to first order);
//   rounded a worn flat, the haversine d/2 (1 + cos(2 pi R psi / L)) over the
//           arc |R psi| <= L/2, same depth, smooth edges.
//
// The wheel is treated as following the flat's radial profile (no pivoting on
// the flat's edges), the usual simplification.
#pragma once

namespace railcosim {

enum class FlatShape { chord, rounded };

struct WheelFlatSpec {
  double length = 0;    // L, m
  double diameter = 0;  // D, m
  double angle = 0;     // rad the wheel turns before the flat's centre meets the rail
  FlatShape shape = FlatShape::chord;
  int wheel = 0;  // which wheel of the vehicle (0 = leading)

  bool operator==(const WheelFlatSpec&) const = default;
};

class WheelFlat {
 public:
  // Throws std::invalid_argument unless 0 < L < D.
  explicit WheelFlat(const WheelFlatSpec& spec);
  const WheelFlatSpec& spec() const { return s_; }
  double depth() const { return depth_; }
  double circumference() const;  // pi D: the period in rolled distance
  // f(s) >= 0, m, and df/ds.
  double loss(double rolled) const;
  double loss_slope(double rolled) const;
  // Rolled distance at which the flat's centre meets the rail the n-th time.
  double impact_position(int n) const;

 private:
  double angle_from_centre(double rolled) const;  // psi in (-pi, pi]
  bool on_flat(double psi) const;
  WheelFlatSpec s_;
  double radius_, half_angle_, depth_;
};

}  // namespace railcosim
