#include "scene.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "excitation_toml.hpp"
#include "scene_checks.hpp"

namespace railcosim {
namespace {

// Reads typed keys from a TOML document and remembers which it consumed, so
// that anything left over can be reported as an unknown key.
class Reader {
 public:
  Reader(const toml::table& root, std::string source) : root_(root), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(source_ + ": key '" + key + "': " + what);
  }

  const toml::node* find(const std::string& table, const std::string& key, bool required) {
    used_[table].insert(key);
    const auto* tbl = root_.get(table) ? root_.get(table)->as_table() : nullptr;
    const toml::node* node = tbl ? tbl->get(key) : nullptr;
    if (!node && required) fail(table + "." + key, "missing (every scene must set it)");
    return node;
  }

  double number(const std::string& table, const std::string& key) {
    return number_or(table, key, std::nullopt);
  }
  double number_or(const std::string& table, const std::string& key,
                   std::optional<double> fallback) {
    const toml::node* n = find(table, key, !fallback.has_value());
    if (!n) return *fallback;
    if (auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer())) {
      if (!std::isfinite(*v)) fail(table + "." + key, "must be a finite number");
      return *v;
    }
    fail(table + "." + key, "must be a number");
  }
  long integer(const std::string& table, const std::string& key) {
    const toml::node* n = find(table, key, true);
    if (!n->is_integer()) fail(table + "." + key, "must be an integer");
    if (auto why = integer_range_error(*n->value<int64_t>()); !why.empty())
      fail(table + "." + key, why);
    return static_cast<long>(*n->value<int64_t>());
  }
  std::string string_or(const std::string& table, const std::string& key, std::string fallback) {
    const toml::node* n = find(table, key, false);
    if (!n) return fallback;
    if (!n->is_string()) fail(table + "." + key, "must be a string");
    return *n->value<std::string>();
  }

  // A table read whole by its own parser (which rejects unknown keys
  // itself); nullptr if the file has none.
  const toml::table* whole_table(const std::string& table) {
    const toml::node* n = root_.get(table);
    if (!n) return nullptr;
    const toml::table* t = n->as_table();
    if (!t) fail(table, "must be a table ([" + table + "])");
    for (const auto& [k, v] : *t) {
      (void)v;
      used_[table].insert(std::string(k.str()));
    }
    used_[table];
    return t;
  }

  // Every table and key in the file must have been read.
  void reject_unknown() const {
    for (const auto& [tname, tnode] : root_) {
      const std::string table(tname.str());
      const auto it = used_.find(table);
      if (it == used_.end()) fail(table, "unknown table");
      const auto* tbl = tnode.as_table();
      if (!tbl) fail(table, "must be a table ([" + table + "])");
      for (const auto& [kname, knode] : *tbl) {
        (void)knode;
        if (!it->second.count(std::string(kname.str())))
          fail(table + "." + std::string(kname.str()), "unknown key");
      }
    }
  }

 private:
  const toml::table& root_;
  std::string source_;
  std::map<std::string, std::set<std::string>> used_;
};

}  // namespace

double Scene::winkler_beta() const {
  const double support = pad_stiffness * ballast_stiffness / (pad_stiffness + ballast_stiffness);
  const double k = support / sleeper_spacing;
  return std::pow(k / (4.0 * young_modulus * second_moment), 0.25);
}

VehicleModel Scene::vehicle_model() const {
  return VehicleModel(vehicle);
}

int Scene::wheel_count() const {
  switch (vehicle.type) {
    case VehicleType::wheel:
    case VehicleType::quarter:
      return 1;
    case VehicleType::car:
      return 4;
  }
  return 1;
}

std::vector<double> Scene::wheel_offsets() const {
  if (vehicle.type != VehicleType::car) return {0.0};
  std::vector<double> x;
  const VehicleModel model = vehicle_model();
  for (const WheelDof& w : model.wheels()) x.push_back(w.offset);
  return x;
}

std::pair<double, double> Scene::wheel_path() const {
  const double x0 = rail_start + initial_position;
  return {x0 + wheel_offsets().back(), x0 + speed * end_time};
}

void Scene::size_track(double x0) {
  // A point load on a Winkler beam deflects it as exp(-beta x)(cos + sin): at
  // a distance m its influence has fallen below exp(-beta m). A free end that
  // close changes the deflection under the load by about that much, so
  // m = ln(1 / tolerance) / beta. The rail starts and ends on the sleeper
  // grid of the scene's frame (sleeper i at (i + 1/2) l), so that the load
  // meets the sleepers where it would on a longer track.
  margin = std::log(1.0 / margin_tolerance) / winkler_beta();
  const double l = sleeper_spacing;
  // The track covers every wheel: from the last one at t = 0 to the
  // leading one at t_end.
  const double span = -wheel_offsets().back();
  rail_start = l * std::floor((x0 - span - margin) / l);
  const double rail_end = l * std::ceil((x0 + speed * end_time + margin) / l);
  sleeper_count = static_cast<int>(std::lround((rail_end - rail_start) / l));
  initial_position = x0 - rail_start;
}

long Scene::macro_steps() const {
  return std::lround(end_time / macro_step);
}

void Scene::validate() const {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw SceneError(source + ": key '" + key + "': " + what);
  };
  auto positive = [&](const std::string& key, double v) {
    if (!(v > 0.0)) {
      std::ostringstream s;
      s << "must be positive (got " << v << ")";
      fail(key, s.str());
    }
  };
  auto non_negative = [&](const std::string& key, double v) {
    if (!(v >= 0.0)) {
      std::ostringstream s;
      s << "must be zero or positive (got " << v << ")";
      fail(key, s.str());
    }
  };
  check_scene_numbers(*this);  // scene_checks.hpp
  positive("vehicle.mass", vehicle_mass);
  positive("vehicle.hertz_constant", hertz_constant);
  non_negative("vehicle.speed_kmh", speed);
  positive("rail.young_modulus", young_modulus);
  positive("rail.second_moment", second_moment);
  positive("rail.area", area);
  positive("rail.density", density);
  if (elements_per_span < 2 || elements_per_span % 2 != 0)
    fail("rail.elements_per_span",
         "must be a positive even number, so that a rail node sits over each sleeper (got " +
             std::to_string(elements_per_span) + ")");
  positive("railpad.stiffness", pad_stiffness);
  non_negative("railpad.damping", pad_damping);
  positive("sleepers.mass", sleeper_mass);
  positive("sleepers.spacing", sleeper_spacing);
  if (!(sleeper_length > 0.0 && sleeper_length <= 10.0))
    fail("sleepers.length", "must lie in (0, 10] m (got " + std::to_string(sleeper_length) + ")");
  if (sleeper_count < 1) fail("sleepers.count", "must be at least 1");
  positive("ballast.stiffness", ballast_stiffness);
  non_negative("ballast.damping", ballast_damping);
  if (soil_model != "fixed" && soil_model != "lumped" && soil_model != "external" &&
      soil_model != "fe")
    fail("soil.model",
         "unknown soil model '" + soil_model + "' (known: fixed, lumped, external, fe)");
  if (soil_model == "lumped") {
    positive("soil.mass", soil_mass);
    positive("soil.stiffness", soil_stiffness);
    non_negative("soil.damping", soil_damping);
    non_negative("soil.coupling_stiffness", soil_coupling_stiffness);
    non_negative("soil.coupling_damping", soil_coupling_damping);
  }
  if (restart != "consistent" && restart != "carry")
    fail("simulation.restart", "must be \"consistent\" or \"carry\"");
  if (micro_steps < 0 || micro_steps > 65536)
    fail("simulation.micro_steps", "must lie between 1 and 65536, or be left out (adaptive)");
  positive("simulation.gravity", gravity);
  positive("simulation.end_time", end_time);
  positive("simulation.macro_step", macro_step);
  positive("simulation.tolerance", tolerance);
  const double steps = end_time / macro_step;
  if (std::abs(steps - std::round(steps)) > 1e-9 * steps)
    fail("simulation.end_time", "must be a whole number of macro steps (end_time / macro_step = " +
                                    std::to_string(steps) + ")");
  if (irregularity.model == "csv" && !irregularity.table_x.empty()) {
    const auto [a, b] = wheel_path();
    try {
      TableProfile(irregularity.table_x, irregularity.table_r, irregularity.csv_path)
          .check_covers(a, b);
    } catch (const SceneError& e) {
      fail("irregularity.file", e.what());
    }
  }
  positive("cosim.divergence_factor", divergence_factor);
  positive("cosim.amplification_threshold", amplification_threshold);

  const double length = track_length();
  auto on_rail = [&](double x) { return x >= 0.0 && x <= length; };
  if (!on_rail(initial_position)) {
    std::ostringstream s;
    s << "the load starts at x = " << initial_position << " m, outside the rail [0, " << length
      << "] m";
    fail("vehicle.initial_position", s.str());
  }
  const double last_wheel = initial_position + wheel_offsets().back();
  if (!on_rail(last_wheel)) {
    std::ostringstream s;
    s << "the last wheel starts at x = " << last_wheel << " m, outside the rail [0, " << length
      << "] m (the vehicle spans " << -wheel_offsets().back()
      << " m behind its leading wheel: move it forward or lengthen the track)";
    fail("vehicle.initial_position", s.str());
  }
  const double x_end = initial_position + speed * end_time;
  if (!on_rail(x_end)) {
    std::ostringstream s;
    s << "the load reaches x = " << x_end << " m at t_end = " << end_time
      << " s, beyond the rail end at " << length << " m (lengthen the track or shorten the run)";
    fail("simulation.end_time", s.str());
  }
  check_scene_derived(*this);  // scene_checks.hpp
}

Scene parse_scene(const std::string& toml_text, const std::string& source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column
      << ": not valid TOML: " << e.description();
    throw SceneError(s.str());
  }
  Reader r(root, source_name);
  Scene sc;
  sc.source = source_name;
  sc.name = r.string_or("scene", "name", "unnamed");

  const toml::table* vehicle = r.whole_table("vehicle");
  if (!vehicle) r.fail("vehicle", "missing table (every scene must have one)");
  sc.vehicle = parse_vehicle(*vehicle, source_name);
  sc.vehicle_mass = sc.vehicle_model().total_mass();
  sc.hertz_constant = sc.vehicle.hertz_constant;
  sc.speed = sc.vehicle.speed;
  sc.initial_position = sc.vehicle.initial_position;
  if (const toml::table* irr = r.whole_table("irregularity"))
    sc.irregularity = parse_irregularity(*irr, source_name);
  if (const toml::table* flat = r.whole_table("wheel_flat"))
    sc.wheel_flat = parse_wheel_flat(*flat, source_name, sc.wheel_count());

  sc.young_modulus = r.number("rail", "young_modulus");
  sc.second_moment = r.number("rail", "second_moment");
  sc.area = r.number("rail", "area");
  sc.density = r.number("rail", "density");
  sc.elements_per_span = static_cast<int>(r.integer("rail", "elements_per_span"));

  sc.pad_stiffness = r.number("railpad", "stiffness");
  sc.pad_damping = r.number("railpad", "damping");

  sc.sleeper_mass = r.number("sleepers", "mass");
  sc.sleeper_spacing = r.number("sleepers", "spacing");
  double x0_scene = 0;
  if (const toml::node* n = r.find("sleepers", "count", true); n->is_string()) {
    if (*n->value<std::string>() != "auto")
      r.fail("sleepers.count", "must be a whole number of sleepers or \"auto\"");
    sc.auto_length = true;
  } else {
    sc.sleeper_count = static_cast<int>(r.integer("sleepers", "count"));
  }
  if (r.find("sleepers", "margin_tolerance", false)) {
    if (!sc.auto_length) r.fail("sleepers.margin_tolerance", "applies only with count = \"auto\"");
    sc.margin_tolerance = r.number("sleepers", "margin_tolerance");
    if (!(sc.margin_tolerance > 0 && sc.margin_tolerance < 1))
      r.fail("sleepers.margin_tolerance", "must lie strictly between 0 and 1");
  }

  if (r.find("sleepers", "length", false)) {
    sc.sleeper_length = r.number("sleepers", "length");
    sc.sleeper_length_given = true;
  }
  sc.ballast_stiffness = r.number("ballast", "stiffness");
  sc.ballast_damping = r.number("ballast", "damping");

  sc.soil_model = r.string_or("soil", "model", "fixed");
  if (sc.soil_model == "external" || sc.soil_model == "fe") {
    // The soil is an outside participant's: its table is that participant's
    // own configuration, with any keys it knows, handed to it whole (as TOML
    // text) at configure time and covered by the scene's fingerprint. The
    // product reads none of its keys but `model` (and, for the FE soil it
    // starts itself, `ranks`; the FE soil checks the others).
    const toml::table* soil = r.whole_table("soil");
    std::ostringstream text;
    text << *soil;
    sc.soil_config = text.str();
    if (sc.soil_model == "fe") {
      if (const toml::node* n = soil->get("ranks")) {
        const auto v = n->value<int64_t>();
        if (!n->is_integer() || !v || *v < 1 || *v > 256)
          r.fail("soil.ranks",
                 "must be a whole number from 1 to 256 (the MPI ranks of the FE soil)");
        sc.soil_ranks = static_cast<int>(*v);
      }
    }
  } else if (sc.soil_model != "fixed") {
    const bool need = sc.soil_model == "lumped";
    auto soil_key = [&](const char* key) {
      return need ? r.number("soil", key) : r.number_or("soil", key, 0.0);
    };
    sc.soil_mass = soil_key("mass");
    sc.soil_stiffness = soil_key("stiffness");
    sc.soil_damping = soil_key("damping");
    sc.soil_coupling_stiffness = soil_key("coupling_stiffness");
    sc.soil_coupling_damping = soil_key("coupling_damping");
  }

  sc.gravity = r.number("simulation", "gravity");
  sc.end_time = r.number("simulation", "end_time");
  sc.macro_step = r.number("simulation", "macro_step");
  sc.tolerance = r.number("simulation", "tolerance");
  sc.restart = r.string_or("simulation", "restart", "consistent");
  if (sc.restart != "consistent" && sc.restart != "carry")
    r.fail("simulation.restart",
           "must be \"consistent\" or \"carry\" (got \"" + sc.restart + "\")");
  if (r.find("simulation", "micro_steps", false)) {
    const long m = r.integer("simulation", "micro_steps");
    if (m < 1 || m > 65536)
      r.fail("simulation.micro_steps", "must lie between 1 and 65536, or be left out (adaptive)");
    sc.micro_steps = static_cast<int>(m);
  }

  sc.divergence_factor = r.number_or("cosim", "divergence_factor", sc.divergence_factor);
  sc.amplification_threshold =
      r.number_or("cosim", "amplification_threshold", sc.amplification_threshold);

  if (const toml::node* n = r.find("output", "ballast_forces", false)) {
    if (!n->is_boolean()) r.fail("output.ballast_forces", "must be true or false");
    sc.ballast_forces = *n->value<bool>();
  }

  r.reject_unknown();
  if (sc.auto_length) {
    x0_scene = sc.initial_position;
    // Check what sizing needs before using it; the full check follows.
    for (const auto& [key, v] : {std::pair{"rail.young_modulus", sc.young_modulus},
                                 {"rail.second_moment", sc.second_moment},
                                 {"railpad.stiffness", sc.pad_stiffness},
                                 {"ballast.stiffness", sc.ballast_stiffness},
                                 {"sleepers.spacing", sc.sleeper_spacing},
                                 {"simulation.end_time", sc.end_time}})
      if (!(v > 0)) r.fail(key, "must be positive");
    if (!(sc.speed >= 0)) r.fail("vehicle.speed_kmh", "must be zero or positive");
    sc.size_track(x0_scene);
  }
  sc.validate();
  return sc;
}

Scene load_scene(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_scene(buf.str(), path);
}

}  // namespace railcosim
