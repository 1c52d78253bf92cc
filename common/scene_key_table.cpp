// The entries of the scene key table (scene_keys.hpp), one per key the
// parsers read, table by table in the order of the reference.
#include <string>
#include <utility>
#include <vector>

#include "scene_checks.hpp"
#include "scene_key_entry.hpp"
#include "scene_keys.hpp"
#include "vehicle_model.hpp"

namespace railcosim {
namespace key_table {
namespace {

const char* const kWheel = "model = \"wheel\"";
const char* const kSprung = "model = \"quarter\" or \"car\"";
const char* const kCar = "model = \"car\"";
const char* const kTrain = "model = \"train\"";

// The keys of the quarter and the car ([vehicle]), or of one car of a train
// (an entry of [[vehicle.cars]]: `train` true; every key applies there).
void sprung_keys(std::vector<Entry>& v, const std::string& table, bool train) {
  const std::string sprung = train ? "" : kSprung, car = train ? "" : kCar;
  auto text = [train](const char* both, const char* car_only) { return train ? car_only : both; };
  v.push_back(number(table, "wheelset_mass", "kg", "one wheelset").range(positive()).when(sprung));
  v.push_back(number(table, "bogie_mass", "kg",
                     text("the bogie share (quarter) or one bogie (car)", "one bogie"))
                  .range(positive())
                  .when(sprung));
  v.push_back(number(table, "body_mass", "kg",
                     text("the body share (quarter) or the body (car)", "the body"))
                  .range(positive())
                  .when(sprung));
  v.push_back(number(table, "primary_stiffness", "N/m",
                     "the primary suspension, between bogie and wheelset (per wheelset)")
                  .range(positive())
                  .when(sprung));
  v.push_back(number(table, "primary_damping", "N s/m", "the primary suspension's damping")
                  .range(non_negative())
                  .when(sprung));
  v.push_back(number(table, "secondary_stiffness", "N/m",
                     "the secondary suspension, between body and bogie (per bogie)")
                  .range(positive())
                  .when(sprung));
  v.push_back(number(table, "secondary_damping", "N s/m", "the secondary suspension's damping")
                  .range(non_negative())
                  .when(sprung));
  v.push_back(number(table, "body_pitch_inertia", "kg m²", "the body's pitch inertia")
                  .range(positive())
                  .when(car));
  v.push_back(number(table, "bogie_pitch_inertia", "kg m²", "one bogie's pitch inertia")
                  .range(positive())
                  .when(car));
  v.push_back(
      number(table, "bogie_semi_spacing", "m", "l_c: half the distance between the bogie centres")
          .range(positive())
          .when(car));
  v.push_back(number(table, "wheelset_semi_base", "m", "l_t: half a bogie's wheelbase")
                  .range(positive())
                  .note("< bogie_semi_spacing")
                  .when(car));
}

void vehicle_keys(std::vector<Entry>& v) {
  v.push_back(choice("vehicle", "model", {"wheel", "quarter", "car", "train"}, "vehicle model",
                     "the vehicle: one wheel carrying the static load (the paper), a quarter car "
                     "(3 DOFs), a car on two bogies (10 DOFs) or a train of such cars (10 DOFs "
                     "each, no couplers)"));
  v.push_back(number("vehicle", "hertz_constant", "N/m^1.5", "K_H of every wheel's Hertz contact")
                  .range(positive()));
  v.push_back(
      number("vehicle", "speed_kmh", "km/h", "the constant speed v_0").range(non_negative()));
  v.push_back(number("vehicle", "initial_position", "m",
                     "x_0: where the leading wheel stands at t = 0, in the scene's frame")
                  .note("every wheel on the rail at t = 0 and at t_end"));
  v.push_back(number("vehicle", "mass", "kg", "the wheel's mass, which carries the static load")
                  .range(positive())
                  .when(kWheel));
  sprung_keys(v, "vehicle", false);
  v.push_back(key("vehicle", "cars", KeyType::tables, "",
                  "the train's cars, front to back: one [[vehicle.cars]] table per car (or per "
                  "run of identical cars, with count)")
                  .note("1 … " + std::to_string(kMaxTrainCars) + " cars in all")
                  .when(kTrain));
  Entry fmu = key("vehicle", "fmu", KeyType::table, "",
                  "an FMU that is the vehicle participant: its mapping keys ([vehicle.fmu]: file, "
                  "CUT_in_QUANTITY, CUT_out_QUANTITY, set_NAME, history_NAME; docs/fmu.md), "
                  "handed to it whole as TOML text; the cases then cut at wr and have no "
                  "monolithic run");
  fmu.k.required = false;
  v.push_back(fmu);
}

// An entry of [[vehicle.cars]]: the car model's keys and where its ends are.
void train_car_keys(std::vector<Entry>& v) {
  const std::string cars = "vehicle.cars";
  sprung_keys(v, cars, true);
  v.push_back(number(cars, "front_overhang", "m",
                     "from the front bogie's centre to the car's front end, where the car "
                     "ahead ends")
                  .range(positive())
                  .note("≥ wheelset_semi_base"));
  v.push_back(number(cars, "rear_overhang", "m",
                     "from the rear bogie's centre to the car's rear end, where the car "
                     "behind begins")
                  .range(positive())
                  .note("≥ wheelset_semi_base"));
  v.push_back(integer(cars, "count", "this many identical cars, one after the other")
                  .range(closed(1, kMaxTrainCars,
                                "must be 1 to " + std::to_string(kMaxTrainCars) + " cars"))
                  .fallback(1));
}

void irregularity_keys(std::vector<Entry>& v) {
  const std::string random = "model = \"random\"";
  const std::string depth = "|value| ≤ " + number_text(kMaxProfileDepth) + " m";
  v.push_back(choice("irregularity", "model", {"none", "random", "csv", "dipped_joint", "sine"},
                     "irregularity model", "the rail's vertical profile (none: smooth)"));
  v.push_back(integer("irregularity", "fra_class", "the FRA track class of the spectrum")
                  .range(closed(1, 6, "must be an FRA track class 1 to 6"))
                  .fallback_text("a_v and omega_c instead")
                  .when(random));
  v.push_back(number("irregularity", "a_v", "cm² rad/m",
                     "the spectrum's roughness A_v, with omega_c instead of fra_class (not both)")
                  .range(positive())
                  .when(random));
  v.push_back(number("irregularity", "omega_c", "rad/m",
                     "the spectrum's cut-off Ω_c, with a_v instead of fra_class")
                  .range(positive())
                  .when(random));
  v.push_back(number("irregularity", "wavelength_min", "m", "the shortest wavelength generated")
                  .range(positive())
                  .when(random));
  v.push_back(number("irregularity", "wavelength_max", "m", "the longest wavelength generated")
                  .range(positive())
                  .note("> wavelength_min")
                  .when(random));
  v.push_back(integer("irregularity", "seed", "the random generator's seed: one seed, one profile")
                  .range({0.0, KeyRange{}.hi, false, false, "must be zero or positive"})
                  .when(random));
  v.push_back(number("irregularity", "amplitude_scale", "", "multiplies the profile")
                  .range({0.0, KeyRange{}.hi, false, false, "must be zero or positive"})
                  .fallback(1.0)
                  .when(random));
  v.push_back(integer("irregularity", "components", "the cosines the profile sums")
                  .range(closed(1, 1000000, "must lie between 1 and 1000000"))
                  .fallback(2048)
                  .note("grid points × components ≤ " + number_text(kMaxProfileWork))
                  .when(random));
  v.push_back(
      number("irregularity", "grid_step", "m",
             "the spacing of the table the profile is interpolated from")
          .range(positive())
          .fallback_text("wavelength_min / 20")
          .note("at most " + number_text(kMaxProfilePoints) + " grid points over the wheels' path")
          .when(random));
  v.push_back(key("irregularity", "file", KeyType::string, "",
                  "a CSV of rows x_m,r_m, relative to the scene file's folder")
                  .note("covers the wheels' path; heights " + depth + "; at most " +
                        std::to_string(kMaxProfileFileBytes / (1024 * 1024)) + " MiB")
                  .when("model = \"csv\""));
  v.push_back(number("irregularity", "position", "m", "the joint's centre")
                  .when("model = \"dipped_joint\""));
  v.push_back(number("irregularity", "length", "m", "the joint's length")
                  .range(positive())
                  .when("model = \"dipped_joint\""));
  v.push_back(number("irregularity", "depth", "m", "the dip's depth")
                  .note(depth)
                  .when("model = \"dipped_joint\""));
  v.push_back(number("irregularity", "amplitude", "m", "A in r = A sin(2π x/λ + φ)")
                  .note(depth)
                  .when("model = \"sine\""));
  v.push_back(
      number("irregularity", "wavelength", "m", "λ").range(positive()).when("model = \"sine\""));
  v.push_back(
      number("irregularity", "phase_deg", "deg", "φ").fallback(0.0).when("model = \"sine\""));
}

void wheel_flat_keys(std::vector<Entry>& v) {
  v.push_back(number("wheel_flat", "length", "m", "the flat's length L along the rail")
                  .range(positive())
                  .note("< wheel_diameter"));
  v.push_back(
      number("wheel_flat", "wheel_diameter", "m", "the wheel's diameter D").range(positive()));
  v.push_back(number("wheel_flat", "angle_deg", "deg",
                     "how far the wheel turns before the flat's centre first meets the rail")
                  .fallback(0.0));
  v.push_back(choice("wheel_flat", "shape", {"chord", "rounded"}, "flat shape",
                     "the exact chord, or a worn flat (a haversine of the same depth)"));
  v.push_back(integer("wheel_flat", "wheel", "the wheel with the flat, counted from the front")
                  .fallback(1)
                  .note("1 … the vehicle's wheels"));
}

void soil_keys(std::vector<Entry>& v) {
  const std::string lumped = "model = \"lumped\"";
  v.push_back(choice("soil", "model", {"fixed", "lumped", "external", "fe", "green"}, "soil model",
                     "fixed: the ballast rests on the ground; lumped: a soil mass under each "
                     "sleeper; external: an outside participant; fe: the finite-element soil; "
                     "green: the soil from the Green's functions of a layered half-space"));
  v.push_back(
      number("soil", "mass", "kg", "m_f, under one sleeper").range(positive()).when(lumped));
  v.push_back(number("soil", "stiffness", "N/m", "k_f, soil mass to the ground")
                  .range(positive())
                  .when(lumped));
  v.push_back(number("soil", "damping", "N s/m", "c_f, soil mass to the ground")
                  .range(non_negative())
                  .when(lumped));
  v.push_back(number("soil", "coupling_stiffness", "N/m", "k_c, between neighbouring soil masses")
                  .range(non_negative())
                  .when(lumped));
  v.push_back(number("soil", "coupling_damping", "N s/m", "c_c, between neighbouring soil masses")
                  .range(non_negative())
                  .when(lumped));
  v.push_back(integer("soil", "ranks", "the MPI ranks the master starts the FE soil on")
                  .range(closed(1, 256,
                                "must be a whole number from 1 to 256 (the MPI ranks of the FE "
                                "soil)"))
                  .fallback(1)
                  .when("model = \"fe\""));
  Entry rest = key("soil", "*", KeyType::table, "",
                   "the outside soil's own configuration, any keys its author defines, handed to "
                   "it whole as TOML text (the FE soil's and the Green's-function soil's keys: "
                   "docs/ground-vibration.md)");
  rest.k.required = false;
  v.push_back(rest.when("model = \"external\", \"fe\" or \"green\""));
}

void simulation_keys(std::vector<Entry>& v) {
  v.push_back(number("simulation", "gravity", "m/s²", "g").range(positive()));
  v.push_back(number("simulation", "end_time", "s", "t_end")
                  .range(positive())
                  .note("a whole number of macro steps, at most " + std::to_string(kMaxMacroSteps) +
                        " of them"));
  v.push_back(
      number("simulation", "macro_step", "s", "H: the communication step").range(positive()));
  v.push_back(number("simulation", "tolerance", "m",
                     "the bound on the local error of one micro step (rotations weighed by the "
                     "element length)")
                  .range(positive())
                  .note("≥ " + number_text(kMinRelativeTolerance) + " × the static deflection"));
  v.push_back(
      integer("simulation", "micro_steps", "that many equal micro steps per macro step")
          .range(closed(1, 65536, "must lie between 1 and 65536, or be left out (adaptive)"))
          .fallback_text("adaptive")
          .note("macro steps × micro_steps ≤ " + number_text(kMaxFixedMicroSteps)));
  v.push_back(choice("simulation", "restart", {"consistent", "carry"}, "",
                     "at communication points: restart from the acceleration the new inputs imply, "
                     "or keep the integrator's"));
  v.push_back(number("cosim", "divergence_factor", "",
                     "a run is diverged when a displacement exceeds this × the largest static one")
                  .range(positive())
                  .fallback(50.0));
  v.push_back(number("cosim", "amplification_threshold", "",
                     "a stable run is inaccurate when its history error exceeds this")
                  .range(positive())
                  .fallback(0.1));
  Entry forces = key("output", "ballast_forces", KeyType::boolean, "",
                     "report the force into the ballast under every sleeper (soil_forces.csv)");
  v.push_back(forces.fallback(0.0));
}

// [coupling]: what `master run` takes unless its flag is given; the
// defaults and ranges are those of the flags (master/cli_run.cpp).
void coupling_keys(std::vector<Entry>& v) {
  Entry method = key("coupling", "implicit", KeyType::boolean, "",
                     "repeat each macro step from a checkpoint until the exchanged values "
                     "converge (--coupling implicit); false: one pass (--coupling explicit)");
  v.push_back(method.fallback(0.0));
  v.push_back(choice("coupling", "inputs",
                     {"hold", "linear", "extrapolate1", "extrapolate2", "waveform0", "waveform1",
                      "waveform2", "waveform3"},
                     "input mode", "what an input does over the macro step (--inputs)"));
  v.push_back(
      choice("coupling", "accelerator", {"constant", "aitken", "iqn-ils"}, "accelerator",
             "implicit coupling: how the iterations of a step are accelerated (--accelerator)")
          .fallback_text("iqn-ils"));  // a choice's default other than its first
  v.push_back(
      number("coupling", "relaxation", "",
             "implicit coupling: the constant factor, the first factor of aitken and iqn-ils "
             "(--relaxation)")
          .range(closed(1e-6, 1.0, "must lie between 1e-6 and 1"))
          .fallback(0.5));
  v.push_back(integer("coupling", "max_iterations",
                      "implicit coupling: iterations per macro step (--max-iterations)")
                  .range(closed(1, 10000, "must lie between 1 and 10000"))
                  .fallback(50));
  v.push_back(integer("coupling", "iteration_budget",
                      "implicit coupling: iterations over the whole run, 0: 50 per macro step of "
                      "the run (--iteration-budget)")
                  .range(closed(0, 1e10, "must lie between 0 and 10000000000"))
                  .fallback(0));
  v.push_back(number("coupling", "convergence", "",
                     "implicit coupling: the relative residual every exchanged quantity must reach "
                     "(--convergence)")
                  .range(closed(1e-15, 0.5, "must lie between 1e-15 and 0.5"))
                  .fallback(1e-8));
  v.push_back(integer("coupling", "reused_windows",
                      "implicit coupling, iqn-ils: past macro steps whose iterations it reuses "
                      "(--reused-windows)")
                  .range(closed(0, 100, "must lie between 0 and 100"))
                  .fallback(8));
  v.push_back(choice("coupling", "feedthrough", {"lagged", "resolved"}, "feedthrough",
                     "Jacobi with an xt cut: when a force output is read (--feedthrough)"));
  v.push_back(choice("coupling", "data_plane", {"direct", "relay"}, "data plane",
                     "over TCP: the nodes send each other their coupling data, or every value "
                     "goes through the master (--data-plane)"));
  v.push_back(
      integer("coupling", "window_steps",
              "direct data plane: macro steps per window, 0: the whole run (--window-steps)")
          .range(closed(0, 1e9, "must lie between 0 and 1000000000"))
          .fallback(0));
  v.push_back(
      number("coupling", "step_budget", "s", "over TCP: a step's time limit (--step-budget)")
          .range(closed(0.1, 86400, "must lie between 0.1 and 86400"))
          .fallback(120));
  v.push_back(number("coupling", "step_deadline_floor", "s",
                     "over TCP: the least a silent step is waited for, on both data planes "
                     "(--step-deadline-floor)")
                  .range(closed(0.1, 86400, "must lie between 0.1 and 86400"))
                  .fallback(2));
  v.push_back(choice("coupling", "judge", {"full", "stability", "none"}, "judgement",
                     "what is judged after the run (--judge)"));
  v.push_back(
      number("coupling", "judge_budget", "", "the Arnoldi measure's budget (--judge-budget)")
          .range(closed(0, 1000, "must lie between 0 and 1000"))
          .fallback(1));
  for (const char* cut : {"wr", "rs", "ss"})
    v.push_back(number("coupling", std::string(cut) + "_macro_step", "s",
                       std::string("the window of the ") + cut +
                           " cut, an integer multiple of simulation.macro_step (leave it "
                           "out for simulation.macro_step; 0 is refused) (--macro-step " +
                           cut + "=H)")
                    .range(closed(0, 1e6, "must lie between 0 and 1e6"))
                    .fallback(0));
}

void track_keys(std::vector<Entry>& v) {
  v.push_back(number("rail", "young_modulus", "Pa", "E").range(positive()));
  v.push_back(
      number("rail", "second_moment", "m⁴", "I, about the horizontal axis").range(positive()));
  v.push_back(number("rail", "area", "m²", "the cross-section A").range(positive()));
  v.push_back(number("rail", "density", "kg/m³", "ρ").range(positive()));
  v.push_back(integer("rail", "elements_per_span", "beam elements between two sleepers")
                  .note("even, 2 … " + std::to_string(kMaxElementsPerSpan)));
  v.push_back(number("railpad", "stiffness", "N/m", "k_p, one pad").range(positive()));
  v.push_back(number("railpad", "damping", "N s/m", "d_p, one pad").range(non_negative()));
  v.push_back(
      number("sleepers", "mass", "kg", "m_s: one rail's share of a sleeper").range(positive()));
  v.push_back(number("sleepers", "spacing", "m", "l, between sleeper centres").range(positive()));
  v.push_back(integer("sleepers", "count",
                      "the sleepers (the rail spans [0, count × spacing]), or \"auto\": the "
                      "wheels' path and a margin on each side")
                  .words({"auto"})
                  .note("1 … " + std::to_string(kMaxSleepers)));
  v.push_back(number("sleepers", "margin_tolerance", "",
                     "how much the free ends may change the deflection under the wheel "
                     "(relative); sets the margin")
                  .range({0.0, 1.0, true, true, "must lie strictly between 0 and 1"})
                  .fallback(1e-4)
                  .when("count = \"auto\""));
  v.push_back(number("sleepers", "length", "m",
                     "across the track: with the spacing, the footprint of a coupling point at "
                     "the ss cut")
                  .range({0.0, 10.0, true, false, "must lie in (0, 10] m", KeyRange::Got::fixed})
                  .fallback(2.6));
  v.push_back(number("ballast", "stiffness", "N/m", "k_b, under one sleeper").range(positive()));
  v.push_back(
      number("ballast", "damping", "N s/m", "d_b, under one sleeper").range(non_negative()));
  layer_keys(v);
  soil_keys(v);
  simulation_keys(v);
}
}  // namespace
}  // namespace key_table

const std::vector<SceneKey>& scene_keys() {
  using namespace key_table;  // NOLINT: the table's own vocabulary, in this function only
  static const std::vector<SceneKey> table = [] {
    std::vector<Entry> v;
    v.push_back(key("scene", "name", KeyType::string, "", "the scene's name, in reports")
                    .fallback_text("unnamed"));
    vehicle_keys(v);
    train_car_keys(v);
    irregularity_keys(v);
    wheel_flat_keys(v);
    track_keys(v);
    coupling_keys(v);
    std::vector<SceneKey> keys;
    for (Entry& e : v) keys.push_back(std::move(e.k));
    return keys;
  }();
  return table;
}

}  // namespace railcosim
