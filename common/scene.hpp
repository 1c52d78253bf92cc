// A scene: every physical and numerical parameter of one study, read from a
// TOML file (see scenes/paper.toml). The physics never hard-codes a value.
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "irregularity.hpp"
#include "outside_soil.hpp"
#include "scene_error.hpp"
#include "vehicle_model.hpp"
#include "wheel_flat.hpp"

namespace railcosim {

// [coupling] (optional): how `master run` couples the participants unless its
// command line says otherwise (a flag given wins); each member is unset when
// the scene leaves its key out. The names are those of the flags' values.
struct SceneCoupling {
  std::optional<bool> implicit;               // --coupling implicit (true) or explicit
  std::optional<std::string> inputs;          // --inputs
  std::optional<std::string> accelerator;     // --accelerator
  std::optional<double> relaxation;           // --relaxation
  std::optional<long> max_iterations;         // --max-iterations
  std::optional<long> iteration_budget;       // --iteration-budget
  std::optional<double> convergence;          // --convergence
  std::optional<long> reused_windows;         // --reused-windows
  std::optional<std::string> feedthrough;     // --feedthrough
  std::optional<std::string> data_plane;      // --data-plane
  std::optional<long> window_steps;           // --window-steps
  std::optional<double> step_budget;          // --step-budget, s
  std::optional<double> step_deadline_floor;  // --step-deadline-floor, s
  std::optional<std::string> judge;           // --judge
  std::optional<double> judge_budget;         // --judge-budget
  // A cut's own window (--macro-step CUT=H_cut), s: an integer multiple of
  // the finest window simulation.macro_step.
  std::optional<double> wr_macro_step, rs_macro_step, ss_macro_step;
  bool given = false;  // the scene has the table

  bool operator==(const SceneCoupling&) const = default;
};

// The files a scene names (an [irregularity] profile), by the name the scene
// gives them, with their contents: read from disk next to the scene file, or
// handed over with the scene's text (a node gets them from the master).
using SceneFiles = std::map<std::string, std::string>;

// A resilient layer of the track: k'' per unit area and a hysteretic loss
// factor, over one rail's share of the area under one sleeper.
struct ResilientLayer {
  double stiffness_per_area = 0;   // k'', N/m^3
  double loss_factor = 0;          // eta
  double area = 0;                 // A, m^2
  double reference_frequency = 0;  // f_ref, Hz: where c = eta k / (2 pi f_ref) holds eta exactly
  double stiffness() const { return stiffness_per_area * area; }  // k = k'' A, N/m
  bool operator==(const ResilientLayer&) const = default;
};

struct Scene {
  std::string source;  // the file it came from, for messages
  // The scene as the parser read it, in canonical form (the TOML document
  // re-written: comments and layout dropped, keys sorted, every number with
  // the digits that give it back exactly), and the files it names. A node
  // parses exactly this (scene_text.hpp): a scene changed after parsing is
  // changed through with_keys(), which keeps the two in step.
  std::string text;
  SceneFiles files;
  std::string name;

  // [vehicle]: model = "wheel" (one wheel carrying the static load m_tot g,
  // the paper), "quarter", "car" or "train" (see vehicle_model.hpp). The four fields
  // below hold for every model; `vehicle` holds the rest.
  double vehicle_mass = 0;      // m_tot, kg: the whole mass one rail carries
  double hertz_constant = 0;    // K_H per wheel, N/m^1.5
  double speed = 0;             // v_0, m/s (the file gives km/h)
  double initial_position = 0;  // x_0 of the leading wheel, m
  VehicleParams vehicle;

  // [irregularity] (absent: a smooth rail) and [wheel_flat] (absent: none).
  // Profile positions are in the scene's frame (x = rail_start + the rail's x).
  IrregularitySpec irregularity;
  std::optional<WheelFlatSpec> wheel_flat;

  // [output] ballast_forces = true: the sleepers' participant reports the
  // force into the ballast under every sleeper at every communication point
  // (soil_forces.csv and its spectra).
  bool ballast_forces = false;

  // [rail]: Euler–Bernoulli beam, free ends.
  double young_modulus = 0;   // E, Pa
  double second_moment = 0;   // I, m^4
  double area = 0;            // A, m^2
  double density = 0;         // rho, kg/m^3
  int elements_per_span = 0;  // N_r, even

  // [railpad]
  double pad_stiffness = 0;  // k_p, N/m
  double pad_damping = 0;    // d_p, N s/m

  // [sleepers]
  double sleeper_mass = 0;     // m_s, kg
  double sleeper_spacing = 0;  // l, m
  // [sleepers] length (optional): across the track, m. With the spacing it
  // gives the footprint of each coupling point at the ss cut (one rail's
  // share of a sleeper bay: spacing x length/2). 2.6 m, a standard concrete
  // sleeper, when the scene does not say.
  double sleeper_length = 2.6;
  bool sleeper_length_given = false;
  int sleeper_count = 0;  // N (computed when the length is automatic)
  // count = "auto": the rail covers the wheel's path plus a margin on each
  // side, chosen so that the truncation changes the deflection under the
  // wheel by less than margin_tolerance (relative).
  bool auto_length = false;
  double margin_tolerance = 1e-4;
  double margin = 0;      // m, when auto_length
  double rail_start = 0;  // x of the rail's left end in the scene's frame, m

  // [ballast]
  double ballast_stiffness = 0;  // k_b, N/m
  double ballast_damping = 0;    // d_b, N s/m
  // [ballast] mass (only with a resilient layer): m_b, the ballast's share
  // under one sleeper, lumped at the interfaces the layers make.
  double ballast_mass = 0;

  // [under_sleeper_pads] (between sleeper and ballast) and
  // [under_ballast_mats] (between ballast and ground or soil), each optional:
  // absent, no layer and no degree of freedom (docs/model.md, "Resilient
  // layers"; common/resilient_layers.hpp).
  std::optional<ResilientLayer> sleeper_pad, ballast_mat;
  bool has_layers() const { return sleeper_pad.has_value() || ballast_mat.has_value(); }
  // One sleeper's support in series (railpad, pad, ballast, mat), N/m: the
  // static stiffness under each rail node over a sleeper.
  double support_stiffness() const;

  // [soil] (see docs/model.md): "fixed" (the ballast rests on the
  // ground), "lumped" (a soil mass under each sleeper), "external" (a
  // participant the product does not model serves it, through the ss cut)
  // or a soil the master starts itself over TCP, through the ss cut
  // (outside_soil.hpp: "fe", the finite-element soil of fe_soil/; "green",
  // the soil from the Green's functions of green_soil/).
  std::string soil_model = "fixed";
  double soil_mass = 0;                // m_f, kg per sleeper
  double soil_stiffness = 0;           // k_f, N/m: soil mass to the ground
  double soil_damping = 0;             // c_f, N s/m
  double soil_coupling_stiffness = 0;  // k_c, N/m: between neighbouring soil masses
  double soil_coupling_damping = 0;    // c_c, N s/m
  // With "external" or a started soil: the whole [soil] table as TOML text, the
  // outside participant's own configuration (any keys it knows); empty
  // otherwise.
  std::string soil_config;
  int soil_ranks = 1;  // "fe": the MPI ranks the master starts it on ([soil] ranks)
  bool has_soil() const { return soil_model != "fixed"; }
  bool builtin_soil() const { return soil_model == "lumped"; }
  // The soil is a participant of its own ("external" or one the master
  // starts): no monolithic reference, only cases through the ss cut.
  bool outside_soil() const { return soil_model == "external" || started_soil() != nullptr; }
  // The vehicle is an FMU ([vehicle.fmu]): a participant of its own at the
  // wheel/rail cut, whose physics the built-in model need not share.
  bool outside_vehicle() const { return !vehicle.fmu_config.empty(); }
  // A participant the product does not model itself: no monolithic run or
  // reference, the co-simulation reference instead.
  bool outside_model() const { return outside_soil() || outside_vehicle(); }
  // The FMU mapping of a role's participant as TOML text (docs/fmu.md): the
  // vehicle's [vehicle.fmu]; the soil's table when it is external and names
  // an FMU (a `file` key); empty otherwise.
  std::string fmu_mapping(const std::string& role) const;
  // The soil the master starts itself (outside_soil.hpp), or nullptr.
  const OutsideSoil* started_soil() const { return find_outside_soil(soil_model); }

  // [simulation]
  double gravity = 0;     // g, m/s^2
  double end_time = 0;    // t_end, s
  double macro_step = 0;  // H, s
  double tolerance = 0;   // bound on the local error of one micro step, m (and rad)
  int micro_steps = 0;    // > 0: that many equal micro steps per macro step (no adaptivity)
  // At communication points: "consistent" (restart from the acceleration the
  // new inputs imply) or "carry" (keep the integrator's acceleration).
  std::string restart = "consistent";

  SceneCoupling coupling;

  // [cosim]: how a co-simulation run is judged.
  double divergence_factor = 50.0;       // |displacement| > factor * static max => diverged
  double amplification_threshold = 0.1;  // history error > threshold => amplified

  double track_length() const { return sleeper_count * sleeper_spacing; }
  // The Winkler wavenumber beta = (k / 4EI)^(1/4) of the rail on its
  // supports smeared along the track (pads and ballast in series), 1/m.
  double winkler_beta() const;
  // Sizes the track from the run (auto_length): sets sleeper_count,
  // rail_start, margin, and moves initial_position into the rail's frame.
  void size_track(double x0_in_scene_frame);
  double element_length() const { return sleeper_spacing / elements_per_span; }
  int rail_nodes() const { return sleeper_count * elements_per_span + 1; }
  double load() const { return vehicle_mass * gravity; }
  // The vehicle model of [vehicle] (its wheels, matrices and loads).
  VehicleModel vehicle_model() const;
  int wheel_count() const;
  // Each wheel's x relative to the leading wheel (0, then <= 0), m.
  std::vector<double> wheel_offsets() const;
  // The stretch of rail the wheels run over during the run, in the scene's
  // frame: from the last wheel at t = 0 to the leading one at t_end.
  std::pair<double, double> wheel_path() const;
  // Macro steps from 0 to end_time (end_time is a whole number of steps).
  long macro_steps() const;

  // Checks every value; throws SceneError naming the key.
  void validate() const;

  bool operator==(const Scene&) const = default;
};

// Reads and validates a scene file. Unknown keys, missing keys, wrong types
// and out-of-range values throw SceneError naming the file and the key.
Scene load_scene(const std::string& path);
// `files`: the files the text names, by name (nullptr: read from disk, next
// to `source_name`); a name missing from `files` is an error naming the key.
Scene parse_scene(const std::string& toml_text, const std::string& source_name,
                  const SceneFiles* files = nullptr);

}  // namespace railcosim
