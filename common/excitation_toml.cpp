#include "excitation_toml.hpp"

#include <filesystem>
#include <numbers>

#include "section_reader.hpp"

namespace railcosim {

VehicleParams parse_vehicle(const toml::table& t, const std::string& source) {
  SectionReader r(t, "vehicle", source);
  VehicleParams p;
  const std::string model = r.has("model") ? r.string("model") : "wheel";
  if (model == "wheel") {
    p.type = VehicleType::wheel;
  } else if (model == "quarter") {
    p.type = VehicleType::quarter;
  } else if (model == "car") {
    p.type = VehicleType::car;
  } else {
    r.fail("model", "unknown vehicle model '" + model + "' (known: wheel, quarter, car)");
  }
  r.set_unknown_hint("for model = \"" + model + "\" (see docs/vehicles.md)");
  p.hertz_constant = r.positive("hertz_constant");
  p.speed = r.non_negative("speed_kmh") / 3.6;
  p.initial_position = r.number("initial_position");
  if (p.type == VehicleType::wheel) {
    p.wheel_mass = r.positive("mass");
  } else {
    p.wheelset_mass = r.positive("wheelset_mass");
    p.bogie_mass = r.positive("bogie_mass");
    p.body_mass = r.positive("body_mass");
    p.primary_stiffness = r.positive("primary_stiffness");
    p.primary_damping = r.non_negative("primary_damping");
    p.secondary_stiffness = r.positive("secondary_stiffness");
    p.secondary_damping = r.non_negative("secondary_damping");
  }
  if (p.type == VehicleType::car) {
    p.body_pitch_inertia = r.positive("body_pitch_inertia");
    p.bogie_pitch_inertia = r.positive("bogie_pitch_inertia");
    p.bogie_semi_spacing = r.positive("bogie_semi_spacing");
    p.wheelset_semi_base = r.positive("wheelset_semi_base");
    if (!(p.wheelset_semi_base < p.bogie_semi_spacing))
      r.fail("wheelset_semi_base",
             "must be less than bogie_semi_spacing (the bogies' wheels "
             "would overlap)");
  }
  r.reject_unknown();
  return p;
}

IrregularitySpec parse_irregularity(const toml::table& t, const std::string& source) {
  SectionReader r(t, "irregularity", source);
  IrregularitySpec s;
  s.model = r.has("model") ? r.string("model") : "none";
  r.set_unknown_hint("for model = \"" + s.model + "\" (see docs/vehicles.md)");
  if (s.model == "random") {
    RandomProfileSpec& g = s.random;
    if (r.has("fra_class")) {
      if (r.has("a_v") || r.has("omega_c"))
        r.fail("fra_class", "give either fra_class or both a_v and omega_c, not both");
      const long c = r.integer_or("fra_class", std::nullopt);
      if (c < 1 || c > 6) r.fail("fra_class", "must be an FRA track class 1 to 6");
      g.psd = fra_class(static_cast<int>(c));
    } else {
      g.psd.a_v = r.positive("a_v");
      g.psd.omega_c = r.positive("omega_c");
    }
    g.wavelength_min = r.positive("wavelength_min");
    g.wavelength_max = r.positive("wavelength_max");
    if (!(g.wavelength_max > g.wavelength_min))
      r.fail("wavelength_max", "must exceed wavelength_min");
    const long seed = r.integer_or("seed", std::nullopt);
    if (seed < 0) r.fail("seed", "must be zero or positive");
    g.seed = static_cast<std::uint64_t>(seed);
    g.amplitude_scale = r.number_or("amplitude_scale", 1.0);
    if (!(g.amplitude_scale >= 0)) r.fail("amplitude_scale", "must be zero or positive");
    const long n = r.integer_or("components", 2048);
    if (n < 1 || n > 1000000) r.fail("components", "must lie between 1 and 1000000");
    g.components = static_cast<int>(n);
    g.grid_step = r.positive_or("grid_step", g.wavelength_min / 20.0);
  } else if (s.model == "csv") {
    const std::string file = r.string("file");
    const std::filesystem::path base = std::filesystem::path(source).parent_path();
    s.csv_path = std::filesystem::path(file).is_absolute() ? file : (base / file).string();
    try {
      const TableProfile table = TableProfile::load_csv(s.csv_path);
      s.table_x = table.xs();
      s.table_r = table.heights();
    } catch (const SceneError& e) {
      r.fail("file", e.what());
    }
  } else if (s.model == "dipped_joint") {
    s.position = r.number("position");
    s.length = r.positive("length");
    s.depth = r.number("depth");
  } else if (s.model == "sine") {
    s.amplitude = r.number("amplitude");
    s.wavelength = r.positive("wavelength");
    s.phase = r.number_or("phase_deg", 0.0) * std::numbers::pi / 180.0;
  } else if (s.model != "none") {
    r.fail("model", "unknown irregularity model '" + s.model +
                        "' (known: none, random, csv, dipped_joint, sine)");
  }
  r.reject_unknown();
  return s;
}

WheelFlatSpec parse_wheel_flat(const toml::table& t, const std::string& source, int wheel_count) {
  SectionReader r(t, "wheel_flat", source);
  WheelFlatSpec f;
  f.length = r.positive("length");
  f.diameter = r.positive("wheel_diameter");
  if (!(f.length < f.diameter)) r.fail("length", "must be shorter than wheel_diameter");
  f.angle = r.number_or("angle_deg", 0.0) * std::numbers::pi / 180.0;
  const std::string shape = r.has("shape") ? r.string("shape") : "chord";
  if (shape == "chord") {
    f.shape = FlatShape::chord;
  } else if (shape == "rounded") {
    f.shape = FlatShape::rounded;
  } else {
    r.fail("shape", "unknown flat shape '" + shape + "' (known: chord, rounded)");
  }
  const long w = r.integer_or("wheel", 1);
  if (w < 1 || w > wheel_count)
    r.fail("wheel", "must be a wheel of the vehicle, 1 to " + std::to_string(wheel_count) +
                        " counted from the front");
  f.wheel = static_cast<int>(w - 1);
  r.reject_unknown();
  return f;
}

}  // namespace railcosim
