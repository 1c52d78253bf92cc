// The values of interfaces as one vector: the arrays of each interface in a
// fixed order (displacement, velocity, force), the interfaces one after the
// other. What the implicit iterations and the coupled statics iterate on.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "participant.hpp"

namespace railcosim::engine {

inline std::array<const std::vector<double>*, 3> arrays(const InterfaceData& d) {
  return {&d.displacement, &d.velocity, &d.force};
}
inline std::array<std::vector<double>*, 3> arrays(InterfaceData& d) {
  return {&d.displacement, &d.velocity, &d.force};
}
// The names of the three arrays, in that order.
inline constexpr const char* kQuantityNames[] = {"displacement", "velocity", "force"};

// Every value of `v`, in order.
inline Eigen::VectorXd flatten(const std::vector<InterfaceData>& v) {
  Eigen::Index size = 0;
  for (const InterfaceData& d : v)
    for (const std::vector<double>* a : arrays(d)) size += static_cast<Eigen::Index>(a->size());
  Eigen::VectorXd f(size);
  Eigen::Index at = 0;
  for (const InterfaceData& d : v)
    for (const std::vector<double>* a : arrays(d))
      for (double e : *a) f[at++] = e;
  return f;
}

// Writes `f` back into `v`, whose arrays give the shape.
inline void unflatten(const Eigen::VectorXd& f, std::vector<InterfaceData>& v) {
  Eigen::Index at = 0;
  for (InterfaceData& d : v)
    for (std::vector<double>* a : arrays(d))
      for (double& e : *a) e = f[at++];
}

}  // namespace railcosim::engine
