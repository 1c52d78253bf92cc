#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "excitation_toml.hpp"
#include "hertz.hpp"
#include "scene.hpp"
#include "test_support.hpp"
#include "vehicle_model.hpp"

namespace railcosim {
namespace {

constexpr double kG = 9.81;
// Statics are solved by a direct factorisation and a Newton iteration run to
// its round-off floor: forces agree with the closed forms to ~1e-12 of the
// weight; 1e-9 leaves room for the condition of the spring matrices.
constexpr double kRel = 1e-9;
// Suspension compressions are 0.01-0.2 m; 1e-10 m is kRel of them.
constexpr double kDeflection = 1e-10;

// One rail's half of the "China Star" power car as tabulated by Zhai, Wang
// & Cai, "Fundamentals of vehicle-track coupled dynamics", Vehicle System
// Dynamics 47(11), 2009: masses and inertias halved, springs per axle box
// (primary) and per bogie side (secondary). scenes/car_irregular.toml gives
// them with how they were checked.
VehicleParams china_star_car() {
  VehicleParams p;
  p.type = VehicleType::car;
  p.hertz_constant = 92.86e9;
  p.speed = 160 / 3.6;
  p.body_mass = 29682.1;
  p.body_pitch_inertia = 0.8615e6;
  p.bogie_mass = 2815.4;
  p.bogie_pitch_inertia = 4743.5;
  p.wheelset_mass = 921.75;
  p.primary_stiffness = 2.3996e6;
  p.primary_damping = 30e3;
  p.secondary_stiffness = 0.8858e6;
  p.secondary_damping = 45e3;
  p.bogie_semi_spacing = 5.73;
  p.wheelset_semi_base = 1.5;
  return p;
}

VehicleParams quarter_of(const VehicleParams& car) {
  VehicleParams p = car;
  p.type = VehicleType::quarter;
  p.body_mass = car.body_mass / 4;    // a car body rests on four wheels per rail
  p.bogie_mass = car.bogie_mass / 2;  // a bogie on two
  p.secondary_stiffness = car.secondary_stiffness / 2;
  p.secondary_damping = car.secondary_damping / 2;
  return p;
}

double compression(const VehicleModel& v, const VehicleStatic& st, const std::string& name) {
  for (const auto& s : v.suspensions())
    if (s.name == name) return s.a.dot(st.u);
  ADD_FAILURE() << "no suspension '" << name << "'";
  return 0;
}

TEST(VehicleModel, WheelCarriesItsWeightThroughHertz) {
  VehicleParams p;
  p.wheel_mass = 11250;
  p.hertz_constant = 92.86e9;
  const VehicleModel v(p);
  ASSERT_EQ(v.dofs(), 1);
  const VehicleStatic st = v.solve_statics({1e-3}, kG);
  EXPECT_NEAR(st.contact_force[0], 11250 * kG, kRel * 11250 * kG);
  EXPECT_NEAR(st.u(0), 1e-3 + hertz_penetration(p.hertz_constant, 11250 * kG), 1e-15);
}

TEST(VehicleModel, QuarterSuspensionDeflectionsAreTheClosedForms) {
  const VehicleParams p = quarter_of(china_star_car());
  const VehicleModel v(p);
  ASSERT_EQ(v.dofs(), 3);
  const VehicleStatic st = v.solve_statics({0.0}, kG);
  const double weight = (p.body_mass + p.bogie_mass + p.wheelset_mass) * kG;
  EXPECT_NEAR(st.contact_force[0], weight, kRel * weight);
  EXPECT_NEAR(compression(v, st, "secondary"), p.body_mass * kG / p.secondary_stiffness,
              kDeflection);
  EXPECT_NEAR(compression(v, st, "primary"),
              (p.body_mass + p.bogie_mass) * kG / p.primary_stiffness, kDeflection);
}

TEST(VehicleModel, CarSharesItsWeightEquallyOverFourWheels) {
  const VehicleParams p = china_star_car();
  const VehicleModel v(p);
  ASSERT_EQ(v.dofs(), 10);
  const double weight = v.total_mass() * kG;
  EXPECT_NEAR(v.total_mass(), p.body_mass + 2 * p.bogie_mass + 4 * p.wheelset_mass, 1e-9);
  // The car is statically determinate: uneven rail tops change no force.
  for (const std::vector<double>& top :
       {std::vector<double>{0, 0, 0, 0}, std::vector<double>{0, 1e-3, -2e-3, 0.5e-3}}) {
    const VehicleStatic st = v.solve_statics(top, kG);
    double sum = 0;
    for (double f : st.contact_force) {
      EXPECT_NEAR(f, weight / 4, kRel * weight);
      sum += f;
    }
    EXPECT_NEAR(sum, weight, kRel * weight);
    // Equilibrium of every DOF: K u = f_g - sum F_i e_i.
    Eigen::VectorXd rhs = v.gravity_load(kG);
    for (std::size_t i = 0; i < v.wheels().size(); ++i)
      rhs(v.wheels()[i].dof) -= st.contact_force[i];
    EXPECT_LT((v.stiffness() * st.u - rhs).cwiseAbs().maxCoeff(), kRel * weight);
    // Each secondary carries half the body; each primary half a bogie's load.
    const double sec = p.body_mass * kG / 2 / p.secondary_stiffness;
    const double prim = (p.body_mass / 2 + p.bogie_mass) * kG / 2 / p.primary_stiffness;
    EXPECT_NEAR(compression(v, st, "secondary front"), sec, kDeflection);
    EXPECT_NEAR(compression(v, st, "secondary rear"), sec, kDeflection);
    for (int w = 1; w <= 4; ++w)
      EXPECT_NEAR(compression(v, st, "primary " + std::to_string(w)), prim, kDeflection);
  }
}

TEST(VehicleModel, CarWheelOffsetsTrailTheLeadingWheel) {
  const VehicleParams p = china_star_car();
  const VehicleModel v(p);
  const double lc = p.bogie_semi_spacing, lt = p.wheelset_semi_base;
  const double expected[4] = {0.0, -2 * lt, -2 * lc, -2 * lc - 2 * lt};
  ASSERT_EQ(v.wheels().size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(v.wheels()[i].offset, expected[i]);
    EXPECT_EQ(v.wheels()[i].dof, 6 + i);
  }
  EXPECT_DOUBLE_EQ(v.span(), 2 * lc + 2 * lt);
}

// Roots lambda = omega^2 of det(K - lambda M) = 0 for M = diag(m1, m2),
// K = [a, -b; -b, c].
std::pair<double, double> two_dof(double m1, double m2, double a, double b, double c) {
  const double A = m1 * m2, B = -(a * m2 + c * m1), C = a * c - b * b;
  const double disc = std::sqrt(B * B - 4 * A * C);
  return {(-B - disc) / (2 * A), (-B + disc) / (2 * A)};
}

TEST(VehicleModel, CarBodyBounceAndPitchOnRigidSupportsMatchClosedForms) {
  const VehicleParams p = china_star_car();
  const VehicleModel v(p);
  // Hold the four wheelsets: the sprung DOFs are the first six.
  const Eigen::MatrixXd K = v.stiffness().topLeftCorner(6, 6);
  const Eigen::MatrixXd M = v.mass().topLeftCorner(6, 6);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  ASSERT_EQ(es.info(), Eigen::Success);
  const Eigen::VectorXd lambda = es.eigenvalues();

  const double ks = p.secondary_stiffness, kp = p.primary_stiffness, lc = p.bogie_semi_spacing;
  // Bounce: body z against both bogies moving together (mass 2 M_t).
  const auto bounce = two_dof(p.body_mass, 2 * p.bogie_mass, 2 * ks, 2 * ks, 2 * ks + 4 * kp);
  // Pitch: l_c phi against the bogies moving in opposition.
  const auto pitch =
      two_dof(p.body_pitch_inertia / (lc * lc), 2 * p.bogie_mass, 2 * ks, 2 * ks, 2 * ks + 4 * kp);
  // Bogie pitch: two primaries at +-l_t, decoupled from the rest.
  const double bogie_pitch =
      2 * kp * p.wheelset_semi_base * p.wheelset_semi_base / p.bogie_pitch_inertia;
  // Eigen's solver reaches ~1e-14 relative on a 6x6 system this well scaled.
  constexpr double kEig = 1e-10;
  for (double expected : {bounce.first, bounce.second, pitch.first, pitch.second, bogie_pitch}) {
    double best = 1e300;
    for (int i = 0; i < lambda.size(); ++i) best = std::min(best, std::abs(lambda(i) - expected));
    EXPECT_LT(best, kEig * expected) << "no eigenvalue near omega^2 = " << expected;
  }
  // The body modes sit near 1 Hz, as a passenger car's should.
  const double f_bounce = std::sqrt(bounce.first) / (2 * std::numbers::pi);
  const double f_pitch = std::sqrt(pitch.first) / (2 * std::numbers::pi);
  EXPECT_GT(f_bounce, 0.5);
  EXPECT_LT(f_bounce, 1.5);
  EXPECT_GT(f_pitch, 0.5);
  EXPECT_LT(f_pitch, 2.0);
  // The classic estimate (springs in series, bogies massless) is within 5%.
  const double series = 2 * ks * 2 * kp / (ks + 2 * kp);
  EXPECT_NEAR(std::sqrt(bounce.first), std::sqrt(series / p.body_mass),
              0.05 * std::sqrt(bounce.first));
}

TEST(VehicleModel, MatricesAreSymmetric) {
  const VehicleModel v(china_star_car());
  EXPECT_TRUE(test::matrices_near(v.stiffness(), v.stiffness().transpose(), 0.0));
  EXPECT_TRUE(test::matrices_near(v.damping(), v.damping().transpose(), 0.0));
}

VehicleParams parse(const std::string& text) {
  const toml::table root = toml::parse(text, std::string_view("car.toml"));
  return parse_vehicle(*root["vehicle"].as_table(), "car.toml");
}

TEST(VehicleToml, WheelKeepsThePaperKeys) {
  const VehicleParams p = parse(
      "[vehicle]\nmass = 11250.0\nhertz_constant = 92.86e9\nspeed_kmh = 300.0\n"
      "initial_position = 2.0\n");
  EXPECT_EQ(p.type, VehicleType::wheel);
  EXPECT_DOUBLE_EQ(p.wheel_mass, 11250.0);
  EXPECT_DOUBLE_EQ(p.speed, 300.0 / 3.6);
  EXPECT_DOUBLE_EQ(p.initial_position, 2.0);
}

const char* kCar =
    "[vehicle]\nmodel = \"car\"\nhertz_constant = 92.86e9\nspeed_kmh = 160.0\n"
    "initial_position = 20.0\nbody_mass = 29682.1\nbody_pitch_inertia = 0.8615e6\n"
    "bogie_mass = 2815.4\nbogie_pitch_inertia = 4743.5\nwheelset_mass = 921.75\n"
    "primary_stiffness = 2.3996e6\nprimary_damping = 30e3\nsecondary_stiffness = 0.8858e6\n"
    "secondary_damping = 45e3\nbogie_semi_spacing = 5.73\nwheelset_semi_base = 1.5\n";

TEST(VehicleToml, CarReadsEveryKey) {
  const VehicleParams p = parse(kCar);
  const VehicleParams q = china_star_car();
  EXPECT_EQ(p.type, VehicleType::car);
  EXPECT_DOUBLE_EQ(p.body_pitch_inertia, q.body_pitch_inertia);
  EXPECT_DOUBLE_EQ(p.bogie_semi_spacing, q.bogie_semi_spacing);
  EXPECT_DOUBLE_EQ(p.secondary_damping, q.secondary_damping);
  EXPECT_DOUBLE_EQ(p.speed, 160.0 / 3.6);
}

void expect_error(const std::string& text, const std::string& fragment) {
  try {
    parse(text);
    ADD_FAILURE() << "no error; expected one with '" << fragment << "'";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("car.toml"), std::string::npos) << e.what();
  }
}

TEST(VehicleToml, ErrorsNameTheFileAndKey) {
  expect_error(std::string(kCar) + "spring = 1.0\n", "'vehicle.spring': unknown key");
  expect_error("[vehicle]\nmodel = \"bus\"\n", "'vehicle.model': unknown vehicle model 'bus'");
  std::string missing = kCar;
  missing.erase(missing.find("bogie_semi_spacing"));
  expect_error(missing, "'vehicle.bogie_semi_spacing': missing");
  std::string negative = kCar;
  negative.replace(negative.find("body_mass = 29682.1"), 19, "body_mass = -1.0");
  expect_error(negative, "'vehicle.body_mass': must be positive");
  // A quarter has no pitch inertia.
  std::string quarter = kCar;
  quarter.replace(quarter.find("\"car\""), 5, "\"quarter\"");
  expect_error(quarter, "'vehicle.body_pitch_inertia': unknown key for model = \"quarter\"");
}

}  // namespace
}  // namespace railcosim
