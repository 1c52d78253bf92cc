#include "scene_checks.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "scene.hpp"

namespace railcosim {
namespace {

[[noreturn]] void fail(const Scene& s, const std::string& key, const std::string& what) {
  std::string m = s.source;
  m += ": key '";
  m += key;
  m += "': ";
  m += what;
  throw SceneError(m);
}

std::string text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Values of one kind (stiffnesses, or masses) that the same matrices add up:
// a spread beyond `ratio` leaves the small ones below the rounding of the
// large ones, and the matrices singular or indefinite in double precision.
// Blames the value farthest (in orders of magnitude) from the geometric mean.
void check_spread(const Scene& s, const std::vector<std::pair<const char*, double>>& values,
                  double ratio, const char* kind) {
  double lo = values.front().second, hi = lo, log_sum = 0;
  for (const auto& [key, v] : values) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    log_sum += std::log10(v);
  }
  if (hi <= lo * ratio) return;
  const double mean = log_sum / static_cast<double>(values.size());
  const std::pair<const char*, double>* worst = &values.front();
  for (const auto& kv : values)
    if (std::abs(std::log10(kv.second) - mean) > std::abs(std::log10(worst->second) - mean))
      worst = &kv;
  std::string what = "gives a ";
  what += kind;
  what += " of " + text(worst->second) + ", while the model's " + kind + "es range from " +
          text(lo) + " to " + text(hi) + ": more than a factor " + text(ratio) +
          " apart, the matrices cannot be solved in double precision";
  fail(s, worst->first, what);
}

// The rail profile's grid, its work and its depth, and the vehicle's path
// over it: bounded before anything is laid out.
void check_excitation(const Scene& s) {
  const IrregularitySpec& irr = s.irregularity;
  const auto [a, b] = s.wheel_path();
  if (irr.model == "random") {
    const RandomProfileSpec& g = irr.random;
    // Without grid_step the parser sets wavelength_min / 20: blame the key
    // the user wrote.
    const bool given = g.grid_step > 0 && g.grid_step != g.wavelength_min / 20.0;
    const double h = g.grid_step > 0 ? g.grid_step : g.wavelength_min / 20.0;
    const char* key = given ? "irregularity.grid_step" : "irregularity.wavelength_min";
    const double points = (b - a) / h + 1.0;
    if (!(points <= kMaxProfilePoints))
      fail(s, key,
           "a grid step of " + text(h) + " m over the wheels' path of " + text(b - a) +
               " m gives " + text(points) + " grid points, more than the " +
               text(kMaxProfilePoints) + " a profile may hold (64 MiB)" +
               (given ? "" : "; the grid step is wavelength_min / 20 unless grid_step is given"));
    if (!(points * g.components <= kMaxProfileWork))
      fail(s, given ? key : "irregularity.components",
           text(points) + " grid points x " + std::to_string(g.components) +
               " components = " + text(points * g.components) + ", more than the " +
               text(kMaxProfileWork) + " a profile may cost to lay (about a second)");
  } else if (irr.model == "dipped_joint") {
    if (!(std::abs(irr.depth) <= kMaxProfileDepth))
      fail(s, "irregularity.depth",
           "a dip of " + text(irr.depth) + " m exceeds " + text(kMaxProfileDepth) +
               " m in magnitude (a rail is 0.17 m high)");
  } else if (irr.model == "sine") {
    if (!(std::abs(irr.amplitude) <= kMaxProfileDepth))
      fail(s, "irregularity.amplitude",
           "an amplitude of " + text(irr.amplitude) + " m exceeds " + text(kMaxProfileDepth) +
               " m in magnitude (a rail is 0.17 m high)");
  } else if (irr.model == "csv") {
    for (std::size_t i = 0; i < irr.table_r.size(); ++i)
      if (!(std::abs(irr.table_r[i]) <= kMaxProfileDepth))
        fail(s, "irregularity.file",
             irr.csv_path + ": its value " + std::to_string(i + 1) + " is a height of " +
                 text(irr.table_r[i]) + " m, more than " + text(kMaxProfileDepth) +
                 " m in magnitude (a rail is 0.17 m high)");
  }
}

}  // namespace

std::string integer_range_error(std::int64_t value) {
  if (value >= INT_MIN && value <= INT_MAX) return "";
  return "out of range (got " + std::to_string(value) + "; at most " + std::to_string(INT_MAX) +
         ")";
}

void check_scene_numbers(const Scene& s) {
  const std::vector<std::pair<const char*, double>> values = {
      {"vehicle.mass", s.vehicle_mass},
      {"vehicle.hertz_constant", s.hertz_constant},
      {"vehicle.speed_kmh", s.speed},
      {"vehicle.initial_position", s.initial_position},
      {"rail.young_modulus", s.young_modulus},
      {"rail.second_moment", s.second_moment},
      {"rail.area", s.area},
      {"rail.density", s.density},
      {"railpad.stiffness", s.pad_stiffness},
      {"railpad.damping", s.pad_damping},
      {"sleepers.mass", s.sleeper_mass},
      {"sleepers.spacing", s.sleeper_spacing},
      {"sleepers.margin_tolerance", s.margin_tolerance},
      {"ballast.stiffness", s.ballast_stiffness},
      {"ballast.damping", s.ballast_damping},
      {"soil.mass", s.soil_mass},
      {"soil.stiffness", s.soil_stiffness},
      {"soil.damping", s.soil_damping},
      {"soil.coupling_stiffness", s.soil_coupling_stiffness},
      {"soil.coupling_damping", s.soil_coupling_damping},
      {"simulation.gravity", s.gravity},
      {"simulation.end_time", s.end_time},
      {"simulation.macro_step", s.macro_step},
      {"simulation.tolerance", s.tolerance},
      {"cosim.divergence_factor", s.divergence_factor},
      {"cosim.amplification_threshold", s.amplification_threshold},
  };
  for (const auto& [key, v] : values) {
    if (v == 0.0) continue;  // each key's own check says whether zero is allowed
    const double a = std::abs(v);
    if (!(a >= kSmallestMagnitude && a <= kLargestMagnitude))
      fail(s, key,
           "must be 0 or lie between " + text(kSmallestMagnitude) + " and " +
               text(kLargestMagnitude) + " in magnitude (got " + text(v) +
               "): the model's arithmetic would overflow or underflow and give NaN");
  }
  if (!std::isfinite(s.rail_start))
    fail(
        s, "vehicle.initial_position",
        "the rail's start in the scene's frame is " + text(s.rail_start) + ", not a finite number");
  if (s.auto_length) {
    // count = "auto": the track the run needs, before it is rounded to a count.
    const double need = (s.speed * s.end_time + 2.0 * s.margin) / s.sleeper_spacing;
    if (!(need <= kMaxSleepers))
      fail(s, "sleepers.count",
           "\"auto\" needs " + text(need) + " sleepers for this run, more than the " +
               std::to_string(kMaxSleepers) +
               " a node accepts (shorten the run, or raise sleepers.margin_tolerance)");
  }
}

namespace {

// The sizes of the run against the nodes' and the master's limits.
void check_run_size(const Scene& s) {
  // The mesh against the nodes' limits, before the master spends any time
  // on the monolithic reference.
  if (s.sleeper_count > kMaxSleepers)
    fail(s, "sleepers.count",
         std::to_string(s.sleeper_count) + " sleepers exceed the limit of " +
             std::to_string(kMaxSleepers) + " (the mesh of a node; about 100,000 DOFs)");
  if (s.elements_per_span > kMaxElementsPerSpan)
    fail(s, "rail.elements_per_span",
         std::to_string(s.elements_per_span) + " elements per span exceed the limit of " +
             std::to_string(kMaxElementsPerSpan));
  // The history of a run is kept in memory: one row per macro step.
  const double steps = s.end_time / s.macro_step;
  if (!(steps <= static_cast<double>(kMaxMacroSteps)))
    fail(s, "simulation.end_time",
         "end_time / macro_step = " + text(steps) + " macro steps, more than the " +
             std::to_string(kMaxMacroSteps) + " a run keeps in memory (some 50 bytes each)");
  if (s.micro_steps > 0 && steps * s.micro_steps > kMaxFixedMicroSteps)
    fail(s, "simulation.micro_steps",
         text(steps) + " macro steps x " + std::to_string(s.micro_steps) +
             " micro steps = " + text(steps * s.micro_steps) + " micro steps, more than the " +
             text(kMaxFixedMicroSteps) +
             " a run may take with fixed micro steps (lower it, or leave it out to adapt)");
}

void check_static_state(const Scene& s) {
  // The static load, its Hertz compression and the deflection of the track
  // under it (Winkler beam: w0 = F beta / 2k): finite and positive, or the
  // static state, and everything after it, is not a number.
  const double load = s.load();
  if (!(std::isfinite(load) && load > 0))
    fail(s, "simulation.gravity",
         "the static load vehicle.mass x gravity = " + text(load) +
             " N is not a finite positive "
             "number");
  const double hertz = std::pow(load / s.hertz_constant, 2.0 / 3.0);
  if (!(std::isfinite(hertz) && hertz > 0))
    fail(s, "vehicle.hertz_constant",
         "the static contact compression (F / K_H)^(2/3) = " + text(hertz) +
             " m is not a finite positive number");
  const double k_smeared = s.support_stiffness() / s.sleeper_spacing;
  const double beta = s.winkler_beta();
  const double w0 = load * beta / (2.0 * k_smeared);
  if (!(std::isfinite(w0) && w0 > 0 && std::isfinite(beta) && beta > 0))
    fail(s, "railpad.stiffness",
         "the static deflection of the track under the load (F beta / 2k, pads and ballast in "
         "series) is " +
             text(w0) + " m, not a finite positive number");
  if (s.tolerance < kMinRelativeTolerance * w0)
    fail(s, "simulation.tolerance",
         text(s.tolerance) + " m is below " + text(kMinRelativeTolerance) +
             " x the static deflection under the load (" + text(w0) +
             " m): the error estimate of a micro step is round-off there and no step meets it");
}

// What the matrices of the track sum: finite, and not too far apart.
void check_matrix_spread(const Scene& s) {
  // The rail element's mass and bending stiffness, which the integrator
  // divides and multiplies by the square of its smallest step.
  const double le = s.element_length();
  const double element_mass = s.density * s.area * le;
  const double element_stiffness = s.young_modulus * s.second_moment / (le * le * le);
  if (!(std::isfinite(element_mass) && element_mass > 0 && std::isfinite(element_stiffness) &&
        element_stiffness > 0))
    fail(s, "rail.density",
         "a rail element (" + text(le) + " m) has mass " + text(element_mass) +
             " kg and bending stiffness " + text(element_stiffness) +
             " N/m: not finite positive numbers");
  // The stiffnesses and masses the same matrices sum, within kMaxSpread of
  // each other (the contact by its tangent stiffness at the static load).
  const double contact = 1.5 * std::pow(s.hertz_constant, 2.0 / 3.0) * std::cbrt(s.load());
  std::vector<std::pair<const char*, double>> k = {{"rail.second_moment", element_stiffness},
                                                   {"railpad.stiffness", s.pad_stiffness},
                                                   {"ballast.stiffness", s.ballast_stiffness},
                                                   {"vehicle.hertz_constant", contact}};
  std::vector<std::pair<const char*, double>> m = {{"vehicle.mass", s.vehicle_mass},
                                                   {"rail.density", element_mass},
                                                   {"sleepers.mass", s.sleeper_mass}};
  if (s.builtin_soil()) {
    k.push_back({"soil.stiffness", s.soil_stiffness});
    m.push_back({"soil.mass", s.soil_mass});
  }
  if (s.sleeper_pad) k.push_back({"under_sleeper_pads.stiffness", s.sleeper_pad->stiffness()});
  if (s.ballast_mat) k.push_back({"under_ballast_mats.stiffness", s.ballast_mat->stiffness()});
  if (s.has_layers()) m.push_back({"ballast.mass", s.ballast_mass});
  check_spread(s, k, kMaxSpread, "stiffness");
  check_spread(s, m, kMaxSpread, "mass");
  // A damper acts through c / h on the same matrices: against its layer's
  // stiffness over one macro step, within kMaxSpread too.
  const std::vector<std::tuple<const char*, double, double>> dampers = {
      {"railpad.damping", s.pad_damping, s.pad_stiffness},
      {"ballast.damping", s.ballast_damping, s.ballast_stiffness},
      {"soil.damping", s.builtin_soil() ? s.soil_damping : 0.0, s.soil_stiffness}};
  for (const auto& [key, c, stiffness] : dampers)
    if (c / s.macro_step > stiffness * kMaxSpread)
      fail(s, key,
           "a damping of " + text(c) + " N s/m acts as " + text(c / s.macro_step) +
               " N/m over one macro step, more than a factor " + text(kMaxSpread) +
               " above its layer's stiffness " + text(stiffness) +
               " N/m: the matrices cannot be solved in double precision");
}

}  // namespace

// A scene's cut windows ([coupling] CUT_macro_step): each an integer
// multiple of the scene's own macro step, as --macro-step CUT=S must be
// (under another --macro-step a window that does not fit it is a default
// left aside, docs/coupling.md).
void check_cut_windows(const Scene& s) {
  const std::pair<const char*, const std::optional<double>*> windows[] = {
      {"coupling.wr_macro_step", &s.coupling.wr_macro_step},
      {"coupling.rs_macro_step", &s.coupling.rs_macro_step},
      {"coupling.ss_macro_step", &s.coupling.ss_macro_step}};
  for (const auto& [key, w] : windows) {
    if (!w->has_value()) continue;
    const double window = **w, k = window / s.macro_step, near = std::round(k);
    if (window == 0)
      fail(s, key,
           "0 is no window: leave the key out for the finest window (simulation.macro_step = " +
               text(s.macro_step) + " s)");
    if (near >= 1 && near <= 1e9 && std::abs(k - near) <= 1e-9 * k) continue;
    const double below = std::max(1.0, std::floor(k)), above = std::max(1.0, std::ceil(k));
    fail(s, key,
         "the window " + text(window) +
             " s is not an integer multiple (at most 1e9) of "
             "simulation.macro_step = " +
             text(s.macro_step) + " s; the nearest multiples are " + text(below * s.macro_step) +
             " s" + (above != below ? " and " + text(above * s.macro_step) + " s" : std::string()));
  }
}

void check_scene_derived(const Scene& s) {
  check_cut_windows(s);
  check_run_size(s);
  check_excitation(s);
  check_static_state(s);
  check_matrix_spread(s);
}

}  // namespace railcosim
