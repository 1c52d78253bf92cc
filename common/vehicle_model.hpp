// The vehicle as a linear second-order system on its wheels' contact points:
//
//   M u'' + C u' + K u = f_g - sum_i F_i e_(wheel i)
//
// with u the vehicle's DOFs (vertical displacements positive DOWN, pitch
// angles positive when the front goes down: a point at s metres ahead of a
// body's centre moves by z + s * phi), f_g the gravity load and F_i >= 0 the
// Hertz force of wheel i (it pushes the wheel up). Four models a scene picks
// with [vehicle] model = ...:
//
//   wheel    1 DOF:  the wheel mass carries the whole load (the paper's scene).
//   quarter  3 DOF:  [body share, bogie share, wheelset]; secondary suspension
//                    between body and bogie, primary between bogie and wheelset.
//   car     10 DOF:  [body z, body phi, front bogie z, phi, rear bogie z, phi,
//                    wheelsets 1..4 z], 2D on one rail. Bogies at +-l_c from
//                    the body centre, wheelsets at +-l_t from their bogie's.
//   train   10 DOF per car: cars as above, front to back, each car's DOFs in
//                    the car's order and named "car K ..." (K from 1). The
//                    cars touch end to end and do not act on one another
//                    (no couplers): each is the car model on its own wheels.
//
// Wheels are numbered from the front (the direction of travel, +x), over the
// whole train. Each wheel's x offset is measured from the leading wheel: 0,
// -2 l_t, -2 l_c, -2 l_c - 2 l_t for the car, so the leading wheel is at the
// vehicle's reference position x_0 + v t and the others trail it. In a train
// car K+1's front end meets car K's rear end, a_K behind its rear bogie's
// centre (rear_overhang), and car K+1's front bogie's centre is f_(K+1)
// behind that front end (front_overhang).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <utility>
#include <vector>

namespace railcosim {

enum class VehicleType { wheel, quarter, car, train };

// The most cars a train may have (all its [[vehicle.cars]] entries with
// their counts): 640 DOFs and 256 wheels.
inline constexpr int kMaxTrainCars = 64;

// One car of a train: the car model's keys (one rail's half, as for
// model = "car") and where its ends are.
struct CarParams {
  double wheelset_mass = 0, bogie_mass = 0, body_mass = 0;  // kg
  double primary_stiffness = 0, primary_damping = 0;        // N/m, N s/m
  double secondary_stiffness = 0, secondary_damping = 0;    // N/m, N s/m
  double body_pitch_inertia = 0, bogie_pitch_inertia = 0;   // kg m^2
  double bogie_semi_spacing = 0;                            // l_c, m
  double wheelset_semi_base = 0;                            // l_t, m
  double front_overhang = 0;  // from the front bogie's centre to the front end, m
  double rear_overhang = 0;   // from the rear bogie's centre to the rear end, m

  bool operator==(const CarParams&) const = default;
};

// Everything [vehicle] gives. Masses, stiffnesses and dampings are those
// carried by ONE rail (the track model is one rail): half the vehicle.
struct VehicleParams {
  VehicleType type = VehicleType::wheel;
  double hertz_constant = 0;    // K_H per wheel, N/m^1.5
  double speed = 0;             // v, m/s (the file gives km/h)
  double initial_position = 0;  // x_0 of the leading wheel, m
  // wheel: the wheel mass, also the whole load (key "mass").
  double wheel_mass = 0;
  // quarter and car (car: bogie_mass is a whole bogie; primary per wheelset;
  // secondary per bogie. quarter: the shares carried by one wheel).
  double wheelset_mass = 0, bogie_mass = 0, body_mass = 0;  // kg
  double primary_stiffness = 0, primary_damping = 0;        // N/m, N s/m
  double secondary_stiffness = 0, secondary_damping = 0;    // N/m, N s/m
  // car only
  double body_pitch_inertia = 0, bogie_pitch_inertia = 0;  // kg m^2
  double bogie_semi_spacing = 0;                           // l_c, m
  double wheelset_semi_base = 0;                           // l_t, m
  // train only: the cars, front to back, one per car (an entry's count
  // written out); their overhangs place them, the keys above stay zero.
  std::vector<CarParams> cars;

  // The FMU that is the vehicle participant ([vehicle.fmu]: its mapping
  // keys, docs/fmu.md) as TOML text, handed to it whole; empty: the
  // built-in vehicle. The keys above still give the speed, the start and
  // the contact the other participants and the statics need.
  std::string fmu_config;
  bool operator==(const VehicleParams&) const = default;
};

const char* to_string(VehicleType t);

// The car model (type car) of one car of a train: the train's contact and
// speed, the car's masses, springs and geometry.
VehicleParams car_of_train(const VehicleParams& train, const CarParams& car);
// Copies a car's model keys (masses, suspensions, l_c, l_t) into p; the
// overhangs stay with the car.
void set_car_keys(VehicleParams& p, const CarParams& car);

// Each wheel's x relative to the leading wheel (0, then <= 0), front to
// back, from the geometry alone: what VehicleModel::wheels() gives.
std::vector<double> wheel_offsets(const VehicleParams& p);

struct WheelDof {
  int dof;        // index into u
  double offset;  // x relative to the leading wheel, m (<= 0)
};

// A spring-damper between two points of the vehicle; its compression is
// a . u (positive when the upper end has moved down relative to the lower).
struct Suspension {
  std::string name;  // "primary 1", "secondary front", ...
  Eigen::VectorXd a;
  double stiffness;
  double damping;
};

// The static state on given rail-top positions (positive down, m) under
// each wheel: velocities zero, M u'' = 0.
struct VehicleStatic {
  Eigen::VectorXd u;                  // all DOFs
  std::vector<double> contact_force;  // F_i, N, per wheel
  std::vector<double> penetration;    // delta_i = q_i - rail_top_i, m
};

class VehicleModel {
 public:
  explicit VehicleModel(const VehicleParams& p);

  const VehicleParams& params() const { return p_; }
  int dofs() const { return static_cast<int>(M_.rows()); }
  const Eigen::MatrixXd& mass() const { return M_; }
  const Eigen::MatrixXd& damping() const { return C_; }
  const Eigen::MatrixXd& stiffness() const { return K_; }
  // f_g: g times the mass of each translational DOF, zero on pitch DOFs
  // (each body's centre of mass is at its pivot).
  Eigen::VectorXd gravity_load(double g) const;
  double total_mass() const;
  const std::vector<WheelDof>& wheels() const { return wheels_; }
  const std::vector<Suspension>& suspensions() const { return susp_; }
  const std::vector<std::string>& dof_names() const { return names_; }
  // Distance from the leading to the trailing wheel, m.
  double span() const { return -wheels_.back().offset; }

  // Solves the statics with each wheel in Hertz contact with its rail top:
  // K u = f_g - sum F_i e_i, F_i = K_H (q_i - rail_top_i)^1.5. The weight
  // goes through every wheel. Throws std::invalid_argument on a size mismatch.
  VehicleStatic solve_statics(const std::vector<double>& rail_top, double g) const;

 private:
  // model = "train": each car's model on the diagonal, car after car.
  void build_train();
  // A suspension whose compression is sum coef * u[dof] over the terms.
  void add_suspension(std::string name, std::vector<std::pair<int, double>> terms, double k,
                      double c);

  VehicleParams p_;
  Eigen::MatrixXd M_, C_, K_;
  std::vector<WheelDof> wheels_;
  std::vector<Suspension> susp_;
  std::vector<std::string> names_;
};

}  // namespace railcosim
