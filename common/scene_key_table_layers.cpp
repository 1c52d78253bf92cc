// The entries of the scene key table for the track's resilient layers
// (common/resilient_layers.hpp): [under_sleeper_pads], [under_ballast_mats]
// and the ballast's mass their interfaces carry.
#include <string>
#include <vector>

#include "scene_key_entry.hpp"

namespace railcosim::key_table {

void layer_keys(std::vector<Entry>& v) {
  const std::string layer = "[under_sleeper_pads] or [under_ballast_mats]";
  v.push_back(number("ballast", "mass", "kg",
                     "m_b: the ballast under one sleeper (one rail's share), carried by the "
                     "layers' interfaces (all of it with one layer, half at each with two)")
                  .range(positive())
                  .when(layer));
  const struct {
    const char* table;
    const char* where;
    const char* above;
  } layers[] = {
      {"under_sleeper_pads", "between each sleeper and the ballast",
       "m the sleeper and the rail over one bay, k the pad in series with the ballast"},
      {"under_ballast_mats", "between the ballast and the ground (or soil)",
       "m the sleeper, the rail over one bay and ballast.mass, k the mat"},
  };
  for (const auto& l : layers) {
    v.push_back(number(l.table, "stiffness", "N/m³",
                       std::string("k'': the layer's stiffness per unit area, ") + l.where)
                    .range(positive()));
    v.push_back(number(l.table, "loss_factor", "",
                       "eta: the hysteretic loss factor, as the damper c = eta k / (2 pi "
                       "reference_frequency)")
                    .range(closed(0, 2, "must lie between 0 and 2")));
    v.push_back(
        number(l.table, "area", "m²",
               "A: the layer's area under one sleeper (one rail's share); k = k'' A")
            .range({0.0, 10.0, true, false, "must lie in (0, 10] m²", KeyRange::Got::fixed}));
    v.push_back(
        number(l.table, "reference_frequency", "Hz",
               "f_ref: where the damper holds the loss factor exactly")
            .range(positive())
            .fallback_text(std::string("the track's resonance on the layer, sqrt(k / m) / 2 pi: ") +
                           l.above));
  }
}

}  // namespace railcosim::key_table
