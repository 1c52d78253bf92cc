// Parsers for the scene tables that choose the vehicle and its excitation:
// [vehicle], [irregularity] and [wheel_flat]. Each takes the table itself
// and the scene file's name (for messages), reads it strictly (unknown keys,
// missing keys, wrong types and out-of-range values throw SceneError naming
// the file and the key) and returns the plain description the models take.
// The keys are documented in docs/vehicles.md.
#pragma once

#include <toml++/toml.h>

#include <string>

#include "irregularity.hpp"
#include "scene.hpp"
#include "vehicle_model.hpp"
#include "wheel_flat.hpp"

namespace railcosim {

// model = "wheel" (default, the paper's keys: mass, hertz_constant,
// speed_kmh, initial_position), "quarter" or "car".
VehicleParams parse_vehicle(const toml::table& vehicle, const std::string& source);

// model = "none" (default), "random", "csv", "dipped_joint" or "sine". A
// csv profile's text comes from `given` (by the name the scene gives it) or,
// when `given` is nullptr, from the file next to `source`; either way it is
// added to `read`.
IrregularitySpec parse_irregularity(const toml::table& irregularity, const std::string& source,
                                    const SceneFiles* given, SceneFiles& read);

// A flat on wheel `wheel` (1-based in the file) of a vehicle with
// `wheel_count` wheels.
WheelFlatSpec parse_wheel_flat(const toml::table& flat, const std::string& source, int wheel_count);

}  // namespace railcosim
