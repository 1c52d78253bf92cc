#include "wheel_flat.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace railcosim {

WheelFlat::WheelFlat(const WheelFlatSpec& spec) : s_(spec) {
  if (!(spec.diameter > 0 && spec.length > 0 && spec.length < spec.diameter))
    throw std::invalid_argument("wheel flat: need 0 < length < diameter");
  radius_ = 0.5 * spec.diameter;
  half_angle_ = std::asin(spec.length / spec.diameter);
  const double half = 0.5 * spec.length;
  // R - sqrt(R^2 - h^2) written without cancellation.
  depth_ = half * half / (radius_ + std::sqrt(radius_ * radius_ - half * half));
}

double WheelFlat::circumference() const {
  return std::numbers::pi * s_.diameter;
}

double WheelFlat::impact_position(int n) const {
  return s_.angle * radius_ + n * circumference();
}

double WheelFlat::angle_from_centre(double rolled) const {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  double psi = std::fmod(rolled / radius_ - s_.angle, two_pi);
  if (psi > std::numbers::pi) psi -= two_pi;
  if (psi <= -std::numbers::pi) psi += two_pi;
  return psi;
}

bool WheelFlat::on_flat(double psi) const {
  // The chord spans the angles +-alpha; the rounded flat the arc +-L/2.
  return s_.shape == FlatShape::chord ? std::abs(psi) <= half_angle_
                                      : std::abs(radius_ * psi) <= 0.5 * s_.length;
}

double WheelFlat::loss(double rolled) const {
  const double psi = angle_from_centre(rolled);
  if (!on_flat(psi)) return 0.0;
  if (s_.shape == FlatShape::chord)
    return radius_ - radius_ * std::cos(half_angle_) / std::cos(psi);
  return 0.5 * depth_ * (1.0 + std::cos(2.0 * std::numbers::pi * radius_ * psi / s_.length));
}

double WheelFlat::loss_slope(double rolled) const {
  const double psi = angle_from_centre(rolled);
  if (!on_flat(psi)) return 0.0;
  // d/ds = (1/R) d/dpsi.
  if (s_.shape == FlatShape::chord)
    return -std::cos(half_angle_) * std::sin(psi) / (std::cos(psi) * std::cos(psi));
  const double k = 2.0 * std::numbers::pi / s_.length;
  return -0.5 * depth_ * k * std::sin(k * radius_ * psi);
}

}  // namespace railcosim
