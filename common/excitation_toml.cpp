#include "excitation_toml.hpp"

#include <filesystem>
#include <numbers>
#include <sstream>

#include "section_reader.hpp"

namespace railcosim {

namespace {

// The keys of the quarter (`pitch` false: the seven shared ones) or of a car
// ([vehicle] or an entry of [[vehicle.cars]]), in the order they are reported.
CarParams read_car(SectionReader& r, bool pitch) {
  CarParams c;
  c.wheelset_mass = r.number("wheelset_mass");
  c.bogie_mass = r.number("bogie_mass");
  c.body_mass = r.number("body_mass");
  c.primary_stiffness = r.number("primary_stiffness");
  c.primary_damping = r.number("primary_damping");
  c.secondary_stiffness = r.number("secondary_stiffness");
  c.secondary_damping = r.number("secondary_damping");
  if (!pitch) return c;
  c.body_pitch_inertia = r.number("body_pitch_inertia");
  c.bogie_pitch_inertia = r.number("bogie_pitch_inertia");
  c.bogie_semi_spacing = r.number("bogie_semi_spacing");
  c.wheelset_semi_base = r.number("wheelset_semi_base");
  if (!(c.wheelset_semi_base < c.bogie_semi_spacing))
    r.fail("wheelset_semi_base",
           "must be less than bogie_semi_spacing (the bogies' wheels "
           "would overlap)");
  return c;
}

// [[vehicle.cars]]: each entry's car, written out `count` times. The number
// of entries and the running total of cars are checked before anything is
// added.
std::vector<CarParams> read_cars(SectionReader& vehicle, const std::string& source) {
  const toml::array& entries = vehicle.tables("cars", kMaxTrainCars);
  std::vector<CarParams> cars;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    SectionReader r(*entries[i].as_table(), "vehicle.cars", source,
                    "vehicle.cars[" + std::to_string(i + 1) + "]");
    r.set_unknown_hint("in an entry of [[vehicle.cars]] (see docs/vehicles.md)");
    CarParams c = read_car(r, true);
    c.front_overhang = r.number("front_overhang");
    c.rear_overhang = r.number("rear_overhang");
    for (const auto& [key, overhang] :
         {std::pair{"front_overhang", c.front_overhang}, {"rear_overhang", c.rear_overhang}})
      if (!(overhang >= c.wheelset_semi_base))
        r.fail(key,
               "must be at least wheelset_semi_base = " + SectionReader::str(c.wheelset_semi_base) +
                   " m (got " + SectionReader::str(overhang) +
                   " m): the outer wheelset would stand beyond the car's end");
    const long count = r.integer("count");
    if (static_cast<long>(cars.size()) + count > kMaxTrainCars)
      r.fail("count", "brings the train to " +
                          std::to_string(cars.size() + static_cast<std::size_t>(count)) +
                          " cars, more than the " + std::to_string(kMaxTrainCars) + " allowed");
    r.reject_unknown();
    cars.insert(cars.end(), static_cast<std::size_t>(count), c);
  }
  return cars;
}

}  // namespace

VehicleParams parse_vehicle(const toml::table& t, const std::string& source) {
  SectionReader r(t, "vehicle", source);
  VehicleParams p;
  const std::string model = r.string("model");
  if (model == "wheel") {
    p.type = VehicleType::wheel;
  } else if (model == "quarter") {
    p.type = VehicleType::quarter;
  } else if (model == "car") {
    p.type = VehicleType::car;
  } else {
    p.type = VehicleType::train;
  }
  r.set_unknown_hint("for model = \"" + model + "\" (see docs/vehicles.md)");
  p.hertz_constant = r.number("hertz_constant");
  p.speed = r.number("speed_kmh") / 3.6;
  p.initial_position = r.number("initial_position");
  if (p.type == VehicleType::wheel) {
    p.wheel_mass = r.number("mass");
  } else if (p.type == VehicleType::train) {
    p.cars = read_cars(r, source);
  } else {
    set_car_keys(p, read_car(r, p.type == VehicleType::car));
  }
  if (const toml::table* fmu = r.subtable("fmu")) {
    std::ostringstream text;
    text << *fmu;
    p.fmu_config = text.str();
  }
  r.reject_unknown();
  return p;
}

IrregularitySpec parse_irregularity(const toml::table& t, const std::string& source,
                                    const SceneFiles* given, SceneFiles& read) {
  SectionReader r(t, "irregularity", source);
  IrregularitySpec s;
  s.model = r.string("model");
  r.set_unknown_hint("for model = \"" + s.model + "\" (see docs/vehicles.md)");
  if (s.model == "random") {
    RandomProfileSpec& g = s.random;
    if (r.has("fra_class")) {
      if (r.has("a_v") || r.has("omega_c"))
        r.fail("fra_class", "give either fra_class or both a_v and omega_c, not both");
      g.psd = fra_class(static_cast<int>(r.integer("fra_class")));
    } else {
      g.psd.a_v = r.number("a_v");
      g.psd.omega_c = r.number("omega_c");
    }
    g.wavelength_min = r.number("wavelength_min");
    g.wavelength_max = r.number("wavelength_max");
    if (!(g.wavelength_max > g.wavelength_min))
      r.fail("wavelength_max", "must exceed wavelength_min");
    g.seed = static_cast<std::uint64_t>(r.integer("seed"));
    g.amplitude_scale = r.number("amplitude_scale");
    g.components = static_cast<int>(r.integer("components"));
    g.grid_step = r.number_or("grid_step", g.wavelength_min / 20.0);
  } else if (s.model == "csv") {
    const std::string file = r.string("file");
    const std::filesystem::path base = std::filesystem::path(source).parent_path();
    s.csv_path = std::filesystem::path(file).is_absolute() ? file : (base / file).string();
    try {
      std::string text;
      if (!given) {
        text = read_profile_file(s.csv_path);
      } else if (const auto it = given->find(file); it != given->end()) {
        text = it->second;
      } else {
        throw SceneError(file + ": not among the files handed over with the scene");
      }
      const TableProfile table = TableProfile::parse_csv(text, s.csv_path);
      read[file] = std::move(text);
      s.table_x = table.xs();
      s.table_r = table.heights();
    } catch (const SceneError& e) {
      r.fail("file", e.what());
    }
  } else if (s.model == "dipped_joint") {
    s.position = r.number("position");
    s.length = r.number("length");
    s.depth = r.number("depth");
  } else if (s.model == "sine") {
    s.amplitude = r.number("amplitude");
    s.wavelength = r.number("wavelength");
    s.phase = r.number("phase_deg") * std::numbers::pi / 180.0;
  }
  r.reject_unknown();
  return s;
}

WheelFlatSpec parse_wheel_flat(const toml::table& t, const std::string& source, int wheel_count) {
  SectionReader r(t, "wheel_flat", source);
  WheelFlatSpec f;
  f.length = r.number("length");
  f.diameter = r.number("wheel_diameter");
  if (!(f.length < f.diameter)) r.fail("length", "must be shorter than wheel_diameter");
  f.angle = r.number("angle_deg") * std::numbers::pi / 180.0;
  f.shape = r.string("shape") == "rounded" ? FlatShape::rounded : FlatShape::chord;
  const long w = r.integer("wheel");
  if (w < 1 || w > wheel_count)
    r.fail("wheel", "must be a wheel of the vehicle, 1 to " + std::to_string(wheel_count) +
                        " counted from the front");
  f.wheel = static_cast<int>(w - 1);
  r.reject_unknown();
  return f;
}

}  // namespace railcosim
