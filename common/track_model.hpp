// Assembly of the wheel/rail/sleeper model, whole or in part.
//
// The monolithic model and every co-simulation subsystem are assembled by the
// same code: a subsystem is the model restricted to the bodies it holds, plus
// the half of the cut element that it keeps (see subsystem.hpp).
#pragma once

#include <memory>
#include <vector>

#include "banded_matrix.hpp"
#include "beam_element.hpp"
#include "irregularity.hpp"
#include "model.hpp"
#include "scene.hpp"
#include "wheel_flat.hpp"

namespace railcosim {

// Global numbering of the degrees of freedom. Each sleeper is numbered right
// after the rail node above it, and its soil mass right after it, which keeps
// the half-bandwidth at 4 (2 N_r + 2 with a lumped soil).
struct DofLayout {
  int wheel = -1;               // the leading wheel (wheels[0])
  std::vector<int> vehicle;     // per DOF of the vehicle model, in its order
  std::vector<int> wheels;      // per wheel, front to back
  std::vector<int> rail_w;      // per rail node: vertical displacement
  std::vector<int> rail_theta;  // per rail node: rotation
  std::vector<int> sleeper;     // per sleeper
  // With resilient layers (resilient_layers.hpp), per sleeper: the ballast's
  // top under an under-sleeper pad, and its bottom on an under-ballast mat.
  std::vector<int> pad_base, mat_top;
  std::vector<int> soil;  // per sleeper: the soil mass under it
  int size = 0;
  int elements_per_span = 0;
  double element_length = 0;  // rail element length, m

  // Rail node under sleeper i.
  int pad_node(int i) const { return elements_per_span * i + elements_per_span / 2; }
  // The lowest DOF of the track under each sleeper, over the element the
  // ss cut goes through: the mat's top, else the pad's base, else the sleeper.
  const std::vector<int>& track_base() const {
    return !mat_top.empty() ? mat_top : !pad_base.empty() ? pad_base : sleeper;
  }
};

DofLayout make_layout(const Scene& scene, const Parts& parts);

// The DOFs of one side of a linear layer (rs, ss), one per coupling point.
std::vector<int> layer_dofs(const DofLayout& layout, int cut, CutSide side);

// Stiffness and damping of one element of a linear layer (rs: a railpad, ss:
// the lowest element under one sleeper, the ballast or an under-ballast mat).
struct SpringDamper {
  double k = 0, c = 0;
};
SpringDamper layer_element(const Scene& scene, int cut);

// Where the moving wheel meets the rail: element and Hermite weights.
struct ContactPoint {
  int element = 0;
  Vector4 shape = Vector4::Zero();  // weights of (w_e, theta_e, w_e+1, theta_e+1)
};

struct ContactPath {
  double x0 = 0, speed = 0, element_length = 0;
  int elements = 0;
  double position(double t) const { return x0 + speed * t; }
  ContactPoint at(double t) const;
};

// What the wheel rolls over besides the rail's deflection: the rail's
// vertical profile r(x) (positive down: a dip) and a flat on the wheel, both
// of which reduce the penetration (see irregularity.hpp).
struct ContactExcitation {
  std::shared_ptr<const RailProfile> profile;  // r(x), x in the scene's frame
  double origin = 0;                           // the rail's x = 0 in the scene's frame
  std::shared_ptr<const WheelFlat> flat;       // on this wheel, if any
  // r(x_c) + f(v t) at the contact point x_c (rail frame) and time t.
  double at(double x_c, double rolled) const {
    double e = 0;
    if (profile) e += profile->height(origin + x_c);
    if (flat) e += flat->loss(rolled);
    return e;
  }
  bool any() const { return profile || flat; }
};

// The contact between one wheel and the rail as a rank-one term of the
// equations of motion. With the penetration delta = g(t)^T u + delta0, the
// contact adds F * g(t) to the internal forces, where g carries +1 on the
// wheel DOF and -N(x_c(t)) on the rail DOFs. A body not held by the system
// enters as a held value in delta0 instead. The sign convention:
//   delta = q - w(x_c) - r(x_c) - f(v t)
// q the wheel's displacement, w the rail's (both positive down), r the
// rail's profile and f the wheel flat's radial loss.
struct ContactTerm {
  enum class Law {
    kHertz,       // F = K_H max(delta, 0)^1.5
    kPrescribed,  // F held (the rail side of an X-T wheel/rail cut)
  };
  Law law = Law::kHertz;
  double hertz_constant = 0;
  bool has_wheel = false;  // else the wheel displacement is held_wheel
  bool has_rail = false;   // else the rail displacement under the wheel is held_rail
  double held_wheel = 0;
  double held_rail = 0;
  double prescribed_force = 0;
  // Held values may ramp linearly over a macro step from their values at t0
  // (interpolated inputs); the rates are zero for a zero-order hold.
  double held_wheel_rate = 0, held_rail_rate = 0, prescribed_force_rate = 0;
  double t0 = 0;
  int wheel = 0;  // which wheel of the vehicle (0 = leading)
  ContactPath path;
  ContactExcitation excitation;

  // The sparse vector g(t): up to 5 (dof, weight) entries.
  struct Entry {
    int dof;
    double weight;
  };
  int entries(double t, const DofLayout& layout, Entry out[5]) const;
  double delta0() const { return (has_wheel ? 0.0 : held_wheel) - (has_rail ? 0.0 : held_rail); }
  double delta0_at(double t) const {
    const double dt = t - t0;
    const double d = (has_wheel ? 0.0 : held_wheel + dt * held_wheel_rate) -
                     (has_rail ? 0.0 : held_rail + dt * held_rail_rate);
    return excitation.any() ? d - excitation.at(path.position(t), path.speed * t) : d;
  }
  // delta0 of the static state at time t (the held values without ramps).
  double static_delta0(double t) const {
    return excitation.any() ? delta0() - excitation.at(path.position(t), path.speed * t) : delta0();
  }
  double prescribed_at(double t) const {
    return prescribed_force + (t - t0) * prescribed_force_rate;
  }
};

// A linear second-order system M a + C v + K u = load, plus an optional
// contact term. This is the whole interface the integrator sees.
struct Structure {
  DofLayout layout;
  SymmetricBandMatrix M, C, K;
  Vector load;       // at load_time; constant over a macro step unless load_rate is set
  Vector load_rate;  // per second, empty for a zero-order hold
  double load_time = 0;
  // The load at time t.
  void load_at(double t, Vector& out) const {
    out = load;
    if (load_rate.size() > 0) out += (t - load_time) * load_rate;
  }
  std::vector<ContactTerm> contacts;  // one per wheel the system touches
};

// Assembles M, C, K, the gravity loads on the vehicle and the contact terms of a
// participant (or of the whole model: Parts::all and no interfaces). A layer
// whose both ends are held is a full element; a layer cut at an interface
// appears on a side that receives displacements as a spring/damper to held
// values (their contribution to the load is added per step), and not at all
// on a side that receives the force.
Structure assemble(const Scene& scene, const ParticipantSpec& participant);

// Rail displacement under the wheel at time t from the rail node values.
double rail_displacement_at(const ContactPath& path, double t, const std::vector<double>& w,
                            const std::vector<double>& theta);

// The path of wheel `wheel` (0 = leading) over the rail.
ContactPath contact_path(const Scene& scene, int wheel = 0);

// The force into the ground under each sleeper (positive down) of a state
// holding the sleepers: through the lowest element (the ballast, or an
// under-ballast mat), k (u_base - u_below) + c (v_base - v_below), above it
// the track's base (DofLayout::track_base), below it the soil mass, the
// ground or the held values of an ss interface.
std::vector<double> ballast_forces(const Scene& scene, const DofLayout& layout, const Vector& u,
                                   const Vector& v, const std::vector<double>* below_u,
                                   const std::vector<double>* below_v);

}  // namespace railcosim
