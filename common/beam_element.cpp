#include "beam_element.hpp"

namespace railcosim {

Matrix4 beam_stiffness(double EI, double L) {
  const double L2 = L * L;
  Matrix4 k;
  k << 12, 6 * L, -12, 6 * L,         //
      6 * L, 4 * L2, -6 * L, 2 * L2,  //
      -12, -6 * L, 12, -6 * L,        //
      6 * L, 2 * L2, -6 * L, 4 * L2;
  return (EI / (L2 * L)) * k;
}

Matrix4 beam_consistent_mass(double rhoA, double L) {
  const double L2 = L * L;
  Matrix4 m;
  m << 156, 22 * L, 54, -13 * L,        //
      22 * L, 4 * L2, 13 * L, -3 * L2,  //
      54, 13 * L, 156, -22 * L,         //
      -13 * L, -3 * L2, -22 * L, 4 * L2;
  return (rhoA * L / 420.0) * m;
}

Vector4 hermite_shape(double xi, double L) {
  const double x2 = xi * xi, x3 = x2 * xi;
  return Vector4(1 - 3 * x2 + 2 * x3, L * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, L * (x3 - x2));
}

}  // namespace railcosim
