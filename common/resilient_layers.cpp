#include "resilient_layers.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "scene_reader.hpp"

namespace railcosim {

double mass_above_pad(const Scene& sc) {
  return sc.sleeper_mass + sc.density * sc.area * sc.sleeper_spacing;
}

double mass_above_mat(const Scene& sc) {
  return mass_above_pad(sc) + sc.ballast_mass;
}

double pad_resonance(const Scene& sc) {
  const double k = 1.0 / (1.0 / sc.sleeper_pad->stiffness() + 1.0 / sc.ballast_stiffness);
  return std::sqrt(k / mass_above_pad(sc)) / (2.0 * std::numbers::pi);
}

double mat_resonance(const Scene& sc) {
  return std::sqrt(sc.ballast_mat->stiffness() / mass_above_mat(sc)) / (2.0 * std::numbers::pi);
}

SpringDamper layer_spring(const ResilientLayer& layer) {
  const double k = layer.stiffness();
  return {k, layer.loss_factor * k / (2.0 * std::numbers::pi * layer.reference_frequency)};
}

double interface_mass(const Scene& sc) {
  return sc.sleeper_pad && sc.ballast_mat ? 0.5 * sc.ballast_mass : sc.ballast_mass;
}

namespace {

ResilientLayer read_layer(SceneReader& r, const std::string& table) {
  ResilientLayer l;
  l.stiffness_per_area = r.number(table, "stiffness");
  l.loss_factor = r.number(table, "loss_factor");
  l.area = r.number(table, "area");
  if (r.present(table, "reference_frequency"))
    l.reference_frequency = r.number(table, "reference_frequency");
  return l;
}

}  // namespace

void read_layers(SceneReader& r, Scene& sc) {
  const bool pad = r.present_table("under_sleeper_pads"),
             mat = r.present_table("under_ballast_mats");
  if (pad) sc.sleeper_pad = read_layer(r, "under_sleeper_pads");
  if (mat) sc.ballast_mat = read_layer(r, "under_ballast_mats");
  if (r.present("ballast", "mass")) {
    if (!pad && !mat)
      r.fail("ballast.mass",
             "applies only with [under_sleeper_pads] or [under_ballast_mats] (without a "
             "resilient layer the ballast is a massless spring and damper)");
    sc.ballast_mass = r.number("ballast", "mass");
  } else if (pad || mat) {
    r.fail("ballast.mass",
           "missing: a resilient layer needs the ballast's mass under one sleeper (kg), which "
           "the layer's interface carries");
  }
  // omega_ref by default: the layer's own resonance on the masses above it.
  if (sc.sleeper_pad && sc.sleeper_pad->reference_frequency == 0)
    sc.sleeper_pad->reference_frequency = pad_resonance(sc);
  if (sc.ballast_mat && sc.ballast_mat->reference_frequency == 0)
    sc.ballast_mat->reference_frequency = mat_resonance(sc);
}

void check_layers(const Scene& sc) {
  auto check = [&](const char* table, const char* key, double v) {
    const std::string why = scene_key(table, key).range.error(v);
    if (!why.empty()) throw SceneError(sc.source + ": key '" + table + "." + key + "': " + why);
  };
  for (const auto& [table, layer] : {std::pair{"under_sleeper_pads", &sc.sleeper_pad},
                                     std::pair{"under_ballast_mats", &sc.ballast_mat}}) {
    if (!layer->has_value()) continue;
    const ResilientLayer& l = **layer;
    check(table, "stiffness", l.stiffness_per_area);
    check(table, "loss_factor", l.loss_factor);
    check(table, "area", l.area);
    check(table, "reference_frequency", l.reference_frequency);
  }
  if (sc.has_layers()) check("ballast", "mass", sc.ballast_mass);
}

}  // namespace railcosim
