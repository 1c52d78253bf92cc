// The monolithic reference: wheel, contact, rail, pads, sleepers and ballast
// integrated as one system from the static equilibrium.
#pragma once

#include <vector>

#include "newmark.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "track_model.hpp"

namespace railcosim {

class MonolithicModel {
 public:
  // output_step: the interval at which the history is recorded and the
  // integrator lands exactly; tolerance: the integrator's local error bound.
  MonolithicModel(const Scene& scene, double output_step, double tolerance);

  // Advances from step n to n + 1 (t = n * output_step).
  void advance(long n);
  HistoryRow history_row(long n) const;
  // The names of history_row's extra values: the channels a co-simulation's
  // participants declare beyond wheel_m and contact_force_N, in load order.
  std::vector<std::string> extra_channels() const;

  // The rail displacement under the wheel at time t (Hermite interpolation).
  double rail_under_wheel(double t) const;

  // Rail node displacements w_k (rotations left out).
  std::vector<double> rail_deflection() const;
  // Soil mass displacements (empty without a lumped soil).
  std::vector<double> soil_deflection() const;
  const Structure& structure() const { return sys_; }
  const Newmark& integrator() const { return newmark_; }
  double output_step() const { return dt_; }

 private:
  Scene scene_;
  Structure sys_;
  double dt_;
  Newmark newmark_;
};

}  // namespace railcosim
