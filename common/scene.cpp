#include "scene.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "excitation_toml.hpp"
#include "resilient_layers.hpp"
#include "scene_checks.hpp"
#include "scene_keys.hpp"
#include "scene_reader.hpp"
#include "toml_nesting.hpp"

namespace railcosim {

double Scene::support_stiffness() const {
  if (!has_layers()) return pad_stiffness * ballast_stiffness / (pad_stiffness + ballast_stiffness);
  double flexibility = 1.0 / pad_stiffness + 1.0 / ballast_stiffness;
  if (sleeper_pad) flexibility += 1.0 / sleeper_pad->stiffness();
  if (ballast_mat) flexibility += 1.0 / ballast_mat->stiffness();
  return 1.0 / flexibility;
}

double Scene::winkler_beta() const {
  const double k = support_stiffness() / sleeper_spacing;
  return std::pow(k / (4.0 * young_modulus * second_moment), 0.25);
}

VehicleModel Scene::vehicle_model() const {
  return VehicleModel(vehicle);
}

int Scene::wheel_count() const {
  return static_cast<int>(wheel_offsets().size());
}

std::vector<double> Scene::wheel_offsets() const {
  return railcosim::wheel_offsets(vehicle);
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

namespace {

// The checks of Scene::validate, in its order: the first failure names the
// file and the key.
class KeyCheck {
 public:
  explicit KeyCheck(const std::string& source) : source_(source) {}
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(source_ + ": key '" + key + "': " + what);
  }
  void positive(const std::string& key, double v) const {
    if (!(v > 0.0)) {
      std::ostringstream s;
      s << "must be positive (got " << v << ")";
      fail(key, s.str());
    }
  }
  // A key's own range, from its entry of the scene key table (the parser
  // checks the same when it reads the file; a scene from the wire comes here).
  void in_range(const char* table, const char* key, double v) const {
    const std::string why = scene_key(table, key).range.error(v);
    if (!why.empty()) fail(std::string(table) + "." + key, why);
  }

 private:
  const std::string& source_;
};

void check_vehicle(const Scene& sc, const KeyCheck& c) {
  c.positive("vehicle.mass", sc.vehicle_mass);
  c.in_range("vehicle", "hertz_constant", sc.hertz_constant);
  c.in_range("vehicle", "speed_kmh", sc.speed);
}

void check_track(const Scene& sc, const KeyCheck& c) {
  c.in_range("rail", "young_modulus", sc.young_modulus);
  c.in_range("rail", "second_moment", sc.second_moment);
  c.in_range("rail", "area", sc.area);
  c.in_range("rail", "density", sc.density);
  if (sc.elements_per_span < 2 || sc.elements_per_span % 2 != 0)
    c.fail("rail.elements_per_span",
           "must be a positive even number, so that a rail node sits over each sleeper (got " +
               std::to_string(sc.elements_per_span) + ")");
  c.in_range("railpad", "stiffness", sc.pad_stiffness);
  c.in_range("railpad", "damping", sc.pad_damping);
  c.in_range("sleepers", "mass", sc.sleeper_mass);
  c.in_range("sleepers", "spacing", sc.sleeper_spacing);
  c.in_range("sleepers", "length", sc.sleeper_length);
  if (sc.sleeper_count < 1) c.fail("sleepers.count", "must be at least 1");
  c.in_range("ballast", "stiffness", sc.ballast_stiffness);
  c.in_range("ballast", "damping", sc.ballast_damping);
  check_layers(sc);
}

void check_soil(const Scene& sc, const KeyCheck& c) {
  if (const std::string why = choice_error(scene_key("soil", "model"), sc.soil_model); !why.empty())
    c.fail("soil.model", why);
  if (sc.soil_model == "lumped") {
    for (const auto& [key, v] : {std::pair{"mass", sc.soil_mass},
                                 {"stiffness", sc.soil_stiffness},
                                 {"damping", sc.soil_damping},
                                 {"coupling_stiffness", sc.soil_coupling_stiffness},
                                 {"coupling_damping", sc.soil_coupling_damping}})
      c.in_range("soil", key, v);
  }
}

void check_simulation(const Scene& sc, const KeyCheck& c) {
  if (!choice_error(scene_key("simulation", "restart"), sc.restart).empty())
    c.fail("simulation.restart", "must be \"consistent\" or \"carry\"");
  if (sc.micro_steps != 0) c.in_range("simulation", "micro_steps", sc.micro_steps);
  c.in_range("simulation", "gravity", sc.gravity);
  c.in_range("simulation", "end_time", sc.end_time);
  c.in_range("simulation", "macro_step", sc.macro_step);
  c.in_range("simulation", "tolerance", sc.tolerance);
  const double steps = sc.end_time / sc.macro_step;
  if (std::abs(steps - std::round(steps)) > 1e-9 * steps)
    c.fail("simulation.end_time",
           "must be a whole number of macro steps (end_time / macro_step = " +
               std::to_string(steps) + ")");
}

void check_irregularity(const Scene& sc, const KeyCheck& c) {
  if (sc.irregularity.model == "csv" && !sc.irregularity.table_x.empty()) {
    const auto [a, b] = sc.wheel_path();
    try {
      TableProfile(sc.irregularity.table_x, sc.irregularity.table_r, sc.irregularity.csv_path)
          .check_covers(a, b);
    } catch (const SceneError& e) {
      c.fail("irregularity.file", e.what());
    }
  }
}

// The vehicle on the rail from the start to the end of the run.
void check_on_rail(const Scene& sc, const KeyCheck& c) {
  const double length = sc.track_length();
  auto on_rail = [&](double x) { return x >= 0.0 && x <= length; };
  if (!on_rail(sc.initial_position)) {
    std::ostringstream s;
    s << "the load starts at x = " << sc.initial_position << " m, outside the rail [0, " << length
      << "] m";
    c.fail("vehicle.initial_position", s.str());
  }
  const double last_wheel = sc.initial_position + sc.wheel_offsets().back();
  if (!on_rail(last_wheel)) {
    std::ostringstream s;
    s << "the last wheel starts at x = " << last_wheel << " m, outside the rail [0, " << length
      << "] m (the vehicle spans " << -sc.wheel_offsets().back()
      << " m behind its leading wheel: move it forward or lengthen the track)";
    c.fail("vehicle.initial_position", s.str());
  }
  const double x_end = sc.initial_position + sc.speed * sc.end_time;
  if (!on_rail(x_end)) {
    std::ostringstream s;
    s << "the load reaches x = " << x_end << " m at t_end = " << sc.end_time
      << " s, beyond the rail end at " << length << " m (lengthen the track or shorten the run)";
    c.fail("simulation.end_time", s.str());
  }
}

}  // namespace

void Scene::validate() const {
  const KeyCheck c(source);
  check_scene_numbers(*this);  // scene_checks.hpp
  check_vehicle(*this, c);
  check_track(*this, c);
  check_soil(*this, c);
  check_simulation(*this, c);
  check_irregularity(*this, c);
  c.in_range("cosim", "divergence_factor", divergence_factor);
  c.in_range("cosim", "amplification_threshold", amplification_threshold);
  check_on_rail(*this, c);
  check_scene_derived(*this);  // scene_checks.hpp
}

namespace {

void read_track(SceneReader& r, Scene& sc) {
  sc.young_modulus = r.number("rail", "young_modulus");
  sc.second_moment = r.number("rail", "second_moment");
  sc.area = r.number("rail", "area");
  sc.density = r.number("rail", "density");
  sc.elements_per_span = static_cast<int>(r.integer("rail", "elements_per_span"));

  sc.pad_stiffness = r.number("railpad", "stiffness");
  sc.pad_damping = r.number("railpad", "damping");

  sc.sleeper_mass = r.number("sleepers", "mass");
  sc.sleeper_spacing = r.number("sleepers", "spacing");
  if (const toml::node* n = r.find("sleepers", "count"); n->is_string()) {
    const SceneKey& count = scene_key("sleepers", "count");
    if (choice_error(count, *n->value<std::string>()) != "")
      r.fail("sleepers.count", "must be a whole number of sleepers or \"auto\"");
    sc.auto_length = true;
  } else {
    sc.sleeper_count = static_cast<int>(r.integer("sleepers", "count"));
  }
  if (r.present("sleepers", "margin_tolerance")) {
    if (!sc.auto_length) r.fail("sleepers.margin_tolerance", "applies only with count = \"auto\"");
    sc.margin_tolerance = r.number("sleepers", "margin_tolerance");
  }
  if (r.present("sleepers", "length")) {
    sc.sleeper_length = r.number("sleepers", "length");
    sc.sleeper_length_given = true;
  }
  sc.ballast_stiffness = r.number("ballast", "stiffness");
  sc.ballast_damping = r.number("ballast", "damping");
  read_layers(r, sc);
}

void read_soil(SceneReader& r, Scene& sc) {
  sc.soil_model = r.string("soil", "model");
  if (sc.outside_soil()) {
    // The soil is an outside participant's: its table is that participant's
    // own configuration, with any keys it knows, handed to it whole (as TOML
    // text) at configure time and covered by the scene's fingerprint. The
    // product reads none of its keys but `model` (and, for a soil it starts
    // itself on MPI ranks, `ranks`; the soil checks the others).
    scene_key("soil", "*");  // the entry of the keys handed on whole
    const toml::table* soil = r.whole_table("soil");
    std::ostringstream text;
    text << *soil;
    sc.soil_config = text.str();
    if (sc.started_soil() != nullptr && sc.started_soil()->mpi) {
      const SceneKey& ranks = scene_key("soil", "ranks");
      sc.soil_ranks = static_cast<int>(default_number(ranks));
      if (const toml::node* n = soil->get("ranks")) {
        const auto v = n->value<int64_t>();
        if (!n->is_integer() || !v || !ranks.range.contains(static_cast<double>(*v)))
          r.fail("soil.ranks", ranks.range.message);
        sc.soil_ranks = static_cast<int>(*v);
      }
    }
  } else if (sc.soil_model == "lumped") {
    sc.soil_mass = r.number("soil", "mass");
    sc.soil_stiffness = r.number("soil", "stiffness");
    sc.soil_damping = r.number("soil", "damping");
    sc.soil_coupling_stiffness = r.number("soil", "coupling_stiffness");
    sc.soil_coupling_damping = r.number("soil", "coupling_damping");
  }
}

// [coupling]: only the keys the scene sets (master run takes them unless
// their flags are given).
void read_coupling(SceneReader& r, Scene& sc) {
  SceneCoupling& c = sc.coupling;
  c.given = r.present_table("coupling");
  auto text = [&](const char* key, std::optional<std::string>& out) {
    if (r.present("coupling", key)) out = r.string("coupling", key);
  };
  auto number = [&](const char* key, std::optional<double>& out) {
    if (r.present("coupling", key)) out = r.number("coupling", key);
  };
  auto whole = [&](const char* key, std::optional<long>& out) {
    if (r.present("coupling", key)) out = r.integer("coupling", key);
  };
  if (r.present("coupling", "implicit")) c.implicit = r.boolean("coupling", "implicit");
  text("inputs", c.inputs);
  text("accelerator", c.accelerator);
  number("relaxation", c.relaxation);
  whole("max_iterations", c.max_iterations);
  whole("iteration_budget", c.iteration_budget);
  number("convergence", c.convergence);
  whole("reused_windows", c.reused_windows);
  text("feedthrough", c.feedthrough);
  text("data_plane", c.data_plane);
  whole("window_steps", c.window_steps);
  number("step_budget", c.step_budget);
  number("step_deadline_floor", c.step_deadline_floor);
  text("judge", c.judge);
  number("judge_budget", c.judge_budget);
  number("wr_macro_step", c.wr_macro_step);
  number("rs_macro_step", c.rs_macro_step);
  number("ss_macro_step", c.ss_macro_step);
}

void read_simulation(SceneReader& r, Scene& sc) {
  sc.gravity = r.number("simulation", "gravity");
  sc.end_time = r.number("simulation", "end_time");
  sc.macro_step = r.number("simulation", "macro_step");
  sc.tolerance = r.number("simulation", "tolerance");
  sc.restart = r.string("simulation", "restart");
  if (r.present("simulation", "micro_steps"))
    sc.micro_steps = static_cast<int>(r.integer("simulation", "micro_steps"));

  sc.divergence_factor = r.number("cosim", "divergence_factor");
  sc.amplification_threshold = r.number("cosim", "amplification_threshold");
  sc.ballast_forces = r.boolean("output", "ballast_forces");
}

}  // namespace

Scene parse_scene(const std::string& toml_text, const std::string& source_name,
                  const SceneFiles* files) {
  // Before the parser, whose recursion a text nested deeply enough would
  // take past the stack.
  check_toml_nesting(toml_text, source_name);
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column
      << ": not valid TOML: " << e.description();
    throw SceneError(s.str());
  }
  SceneReader r(root, source_name);
  Scene sc;
  sc.source = source_name;
  sc.name = r.string("scene", "name");

  const toml::table* vehicle = r.whole_table("vehicle");
  if (!vehicle) r.fail("vehicle", "missing table (every scene must have one)");
  sc.vehicle = parse_vehicle(*vehicle, source_name);
  sc.vehicle_mass = sc.vehicle_model().total_mass();
  sc.hertz_constant = sc.vehicle.hertz_constant;
  sc.speed = sc.vehicle.speed;
  sc.initial_position = sc.vehicle.initial_position;
  if (const toml::table* irr = r.whole_table("irregularity"))
    sc.irregularity = parse_irregularity(*irr, source_name, files, sc.files);
  if (const toml::table* flat = r.whole_table("wheel_flat"))
    sc.wheel_flat = parse_wheel_flat(*flat, source_name, sc.wheel_count());

  read_track(r, sc);
  read_soil(r, sc);
  read_simulation(r, sc);
  read_coupling(r, sc);
  r.reject_unknown();
  std::ostringstream canonical;
  canonical << root;
  sc.text = canonical.str();
  // count = "auto": every value the sizing uses was checked as it was read.
  if (sc.auto_length) sc.size_track(sc.initial_position);
  sc.validate();
  return sc;
}

std::string Scene::fmu_mapping(const std::string& role) const {
  if (role == "vehicle") return vehicle.fmu_config;
  if (role == "soil" && soil_model == "external" && !soil_config.empty() &&
      toml::parse(soil_config).contains("file"))
    return soil_config;
  return "";
}

Scene load_scene(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_scene(buf.str(), path);
}

}  // namespace railcosim
