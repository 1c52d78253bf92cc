#include "scene_numbers.hpp"

#include <cstdint>

namespace railcosim {
namespace {

// The scalar fields of each part, in wire order.
std::vector<double*> vehicle_fields(VehicleParams& p) {
  return {&p.hertz_constant,      &p.speed,
          &p.initial_position,    &p.wheel_mass,
          &p.wheelset_mass,       &p.bogie_mass,
          &p.body_mass,           &p.primary_stiffness,
          &p.primary_damping,     &p.secondary_stiffness,
          &p.secondary_damping,   &p.body_pitch_inertia,
          &p.bogie_pitch_inertia, &p.bogie_semi_spacing,
          &p.wheelset_semi_base};
}

std::vector<double*> irregularity_fields(IrregularitySpec& s) {
  RandomProfileSpec& r = s.random;
  return {&r.psd.k,           &r.psd.a_v,    &r.psd.omega_c, &r.wavelength_min, &r.wavelength_max,
          &r.amplitude_scale, &r.grid_step,  &s.position,    &s.length,         &s.depth,
          &s.amplitude,       &s.wavelength, &s.phase};
}

[[noreturn]] void bad(const std::string& source, const std::string& what) {
  throw SceneError(source + ": " + what);
}

}  // namespace

ExcitationNumbers to_numbers(const Scene& scene) {
  ExcitationNumbers n;
  VehicleParams v = scene.vehicle;
  n.vehicle_model = to_string(v.type);
  for (double* f : vehicle_fields(v)) n.vehicle.push_back(*f);
  IrregularitySpec s = scene.irregularity;
  n.irregularity_model = s.model;
  if (s.model != "none") {
    for (double* f : irregularity_fields(s)) n.irregularity.push_back(*f);
    // The seed as two exact halves (a double holds 53 bits), the component count.
    n.irregularity.push_back(static_cast<double>(s.random.seed >> 32));
    n.irregularity.push_back(static_cast<double>(s.random.seed & 0xffffffffULL));
    n.irregularity.push_back(static_cast<double>(s.random.components));
    for (std::size_t i = 0; i < s.table_x.size(); ++i) {
      n.irregularity.push_back(s.table_x[i]);
      n.irregularity.push_back(s.table_r[i]);
    }
  }
  if (scene.wheel_flat) {
    const WheelFlatSpec& f = *scene.wheel_flat;
    n.wheel_flat = {f.length, f.diameter, f.angle, f.shape == FlatShape::chord ? 0.0 : 1.0,
                    static_cast<double>(f.wheel)};
  }
  return n;
}

void from_numbers(const ExcitationNumbers& n, Scene& scene, const std::string& source) {
  VehicleParams v;
  if (n.vehicle_model == "wheel" || n.vehicle_model.empty())
    v.type = VehicleType::wheel;
  else if (n.vehicle_model == "quarter")
    v.type = VehicleType::quarter;
  else if (n.vehicle_model == "car")
    v.type = VehicleType::car;
  else
    bad(source, "unknown vehicle model '" + n.vehicle_model + "'");
  auto vf = vehicle_fields(v);
  if (n.vehicle.empty()) {
    // A scene from an older master: the paper's wheel.
    v.hertz_constant = scene.hertz_constant;
    v.speed = scene.speed;
    v.initial_position = scene.initial_position;
    v.wheel_mass = scene.vehicle_mass;
  } else if (n.vehicle.size() == vf.size()) {
    for (std::size_t i = 0; i < vf.size(); ++i) *vf[i] = n.vehicle[i];
  } else {
    bad(source, "the vehicle has " + std::to_string(n.vehicle.size()) + " numbers, not " +
                    std::to_string(vf.size()));
  }
  scene.vehicle = v;

  IrregularitySpec s;
  s.model = n.irregularity_model.empty() ? "none" : n.irregularity_model;
  if (s.model != "none") {
    auto f = irregularity_fields(s);
    const std::size_t fixed = f.size() + 3;
    if (n.irregularity.size() < fixed || (n.irregularity.size() - fixed) % 2 != 0)
      bad(source, "the irregularity's numbers do not fit model '" + s.model + "'");
    for (std::size_t i = 0; i < f.size(); ++i) *f[i] = n.irregularity[i];
    const auto hi = static_cast<std::uint64_t>(n.irregularity[f.size()]);
    const auto lo = static_cast<std::uint64_t>(n.irregularity[f.size() + 1]);
    s.random.seed = (hi << 32) | lo;
    s.random.components = static_cast<int>(n.irregularity[f.size() + 2]);
    for (std::size_t i = fixed; i < n.irregularity.size(); i += 2) {
      s.table_x.push_back(n.irregularity[i]);
      s.table_r.push_back(n.irregularity[i + 1]);
    }
    if (s.model == "random" && (s.random.components < 1 || s.random.components > 1000000))
      bad(source, "the random profile's component count is out of range");
  }
  scene.irregularity = s;

  scene.wheel_flat.reset();
  if (!n.wheel_flat.empty()) {
    if (n.wheel_flat.size() != 5) bad(source, "the wheel flat needs 5 numbers");
    WheelFlatSpec f;
    f.length = n.wheel_flat[0];
    f.diameter = n.wheel_flat[1];
    f.angle = n.wheel_flat[2];
    f.shape = n.wheel_flat[3] == 0.0 ? FlatShape::chord : FlatShape::rounded;
    f.wheel = static_cast<int>(n.wheel_flat[4]);
    if (!(f.length > 0 && f.length < f.diameter) || f.wheel < 0 || f.wheel >= scene.wheel_count())
      bad(source, "the wheel flat does not fit the vehicle");
    scene.wheel_flat = f;
  }
}

}  // namespace railcosim
