// The vehicle and excitation parts of a scene as plain numbers, for the
// wire (a node rebuilds the very same model from them: a random profile
// from its seed, a measured one from its rows).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scene.hpp"

namespace railcosim {

struct ExcitationNumbers {
  std::string vehicle_model;  // wheel, quarter, car
  std::vector<double> vehicle;
  std::string irregularity_model;  // none, random, csv, dipped_joint, sine
  std::vector<double> irregularity;
  std::vector<double> wheel_flat;  // empty: no flat
};

ExcitationNumbers to_numbers(const Scene& scene);
// Fills the scene's vehicle, irregularity and wheel_flat; throws SceneError
// naming `source` when the numbers do not fit.
void from_numbers(const ExcitationNumbers& n, Scene& scene, const std::string& source);

}  // namespace railcosim
