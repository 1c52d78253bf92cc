// The train: several cars, front to back, each the car model on its own
// wheels. One car is the car model bit for bit; two different cars are each
// car's matrices on the diagonal, placed by their overhangs; a count writes
// out identical cars; the parser refuses what cannot be a train and names
// the entry and key.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "excitation_toml.hpp"
#include "model.hpp"
#include "scene.hpp"
#include "test_support.hpp"
#include "track_model.hpp"
#include "vehicle_model.hpp"

namespace railcosim {
namespace train_model_test {

// The car of scenes/car_irregular.toml (one rail's half of the China Star
// power car, see that file), as the keys of one car.
const char* kPowerCar =
    "body_mass = 29682.1\nbody_pitch_inertia = 0.8615e6\nbogie_mass = 2815.4\n"
    "bogie_pitch_inertia = 4743.5\nwheelset_mass = 921.75\nprimary_stiffness = 2.3996e6\n"
    "primary_damping = 30e3\nsecondary_stiffness = 0.8858e6\nsecondary_damping = 45e3\n"
    "bogie_semi_spacing = 5.73\nwheelset_semi_base = 1.5\n";
// A second car that differs from the first in every key (made up for the
// test: a lighter trailer on longer bogie centres).
const char* kTrailer =
    "body_mass = 20500.0\nbody_pitch_inertia = 0.61e6\nbogie_mass = 1650.0\n"
    "bogie_pitch_inertia = 1210.0\nwheelset_mass = 880.0\nprimary_stiffness = 1.25e6\n"
    "primary_damping = 21e3\nsecondary_stiffness = 0.41e6\nsecondary_damping = 32e3\n"
    "bogie_semi_spacing = 8.75\nwheelset_semi_base = 1.25\n";
const char* kHead =
    "[vehicle]\nhertz_constant = 92.86e9\nspeed_kmh = 160.0\ninitial_position = 60.0\n";

std::string car_text() {
  return std::string(kHead) + "model = \"car\"\n" + kPowerCar;
}
// An entry of [[vehicle.cars]]: a car's keys and its overhangs.
std::string entry(const char* car, double front, double rear, const std::string& more = "") {
  std::ostringstream s;
  s << "\n[[vehicle.cars]]\n"
    << car << "front_overhang = " << front << "\nrear_overhang = " << rear << "\n"
    << more;
  return s.str();
}
std::string train_text(const std::string& entries) {
  return std::string(kHead) + "model = \"train\"\n" + entries;
}

VehicleParams parse(const std::string& text) {
  const toml::table root = toml::parse(text, std::string_view("train.toml"));
  return parse_vehicle(*root["vehicle"].as_table(), "train.toml");
}

// Bitwise equality of two matrices (their sizes and every bit of every entry).
bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

TEST(TrainModel, OneCarIsTheCarModelBitForBit) {
  const VehicleModel car(parse(car_text()));
  const VehicleModel train(parse(train_text(entry(kPowerCar, 3.2, 3.4))));
  EXPECT_TRUE(same_bits(train.mass(), car.mass()));
  EXPECT_TRUE(same_bits(train.damping(), car.damping()));
  EXPECT_TRUE(same_bits(train.stiffness(), car.stiffness()));
  EXPECT_TRUE(same_bits(train.gravity_load(9.81), car.gravity_load(9.81)));
  ASSERT_EQ(train.wheels().size(), 4u);
  for (std::size_t w = 0; w < 4; ++w) {
    EXPECT_EQ(train.wheels()[w].dof, car.wheels()[w].dof);
    EXPECT_EQ(std::memcmp(&train.wheels()[w].offset, &car.wheels()[w].offset, sizeof(double)), 0)
        << "wheel " << w + 1 << ": " << train.wheels()[w].offset;
  }
  EXPECT_EQ(train.dof_names().front(), "car 1 body z");
  EXPECT_EQ(train.suspensions().front().name, "car 1 secondary front");
  const std::vector<double> top = {0, 0, 0, 0};
  EXPECT_EQ(train.solve_statics(top, 9.81).contact_force,
            car.solve_statics(top, 9.81).contact_force);
}

// Two different cars: each car's own matrices on the diagonal, nothing
// between them, and every wheel where the cars' lengths put it.
TEST(TrainModel, TwoCarsAreEachCarOnTheDiagonalPlacedByTheirOverhangs) {
  const double f1 = 3.2, r1 = 3.4, f2 = 2.6, r2 = 2.9;
  const VehicleParams p = parse(train_text(entry(kPowerCar, f1, r1) + entry(kTrailer, f2, r2)));
  ASSERT_EQ(p.cars.size(), 2u);
  const VehicleModel train(p);
  ASSERT_EQ(train.dofs(), 20);
  for (int k = 0; k < 2; ++k) {
    const VehicleModel car(car_of_train(p, p.cars[static_cast<std::size_t>(k)]));
    const int o = 10 * k, other = 10 - o;
    EXPECT_TRUE(same_bits(train.mass().block(o, o, 10, 10), car.mass())) << k;
    EXPECT_TRUE(same_bits(train.damping().block(o, o, 10, 10), car.damping())) << k;
    EXPECT_TRUE(same_bits(train.stiffness().block(o, o, 10, 10), car.stiffness())) << k;
    for (const Eigen::MatrixXd* m : {&train.mass(), &train.damping(), &train.stiffness()})
      EXPECT_TRUE(m->block(o, other, 10, 10).isZero(0.0)) << k;
    EXPECT_TRUE(same_bits(train.gravity_load(9.81).segment(o, 10), car.gravity_load(9.81)));
  }
  // Closed form: car 1's wheels at 0, -2 lt1, -2 lc1, -2 lc1 - 2 lt1; car
  // 2's front end r1 behind car 1's rear bogie (-lt1 - 2 lc1 - r1), its
  // leading wheel f2 - lt2 behind that, then its own pattern.
  const double lc1 = 5.73, lt1 = 1.5, lc2 = 8.75, lt2 = 1.25;
  const double lead2 = -lt1 - 2 * lc1 - r1 - f2 + lt2;
  const std::vector<double> want = {
      0,     -2 * lt1,        -2 * lc1,        -2 * lc1 - 2 * lt1,
      lead2, lead2 - 2 * lt2, lead2 - 2 * lc2, lead2 - 2 * lc2 - 2 * lt2};
  ASSERT_EQ(train.wheels().size(), want.size());
  for (std::size_t w = 0; w < want.size(); ++w) {
    EXPECT_NEAR(train.wheels()[w].offset, want[w], 1e-13) << "wheel " << w + 1;
    EXPECT_EQ(train.wheels()[w].dof, 10 * static_cast<int>(w / 4) + 6 + static_cast<int>(w % 4));
  }
  EXPECT_EQ(wheel_offsets(p).size(), want.size());
  EXPECT_NEAR(train.span(), -want.back(), 1e-13);
  // Statics: with no coupler, each wheel carries what it carries under its
  // car alone (Newton to round-off on both: 1e-12 of the wheel load).
  const VehicleStatic st = train.solve_statics(std::vector<double>(8, 0.0), 9.81);
  for (std::size_t k = 0; k < 2; ++k) {
    const VehicleModel car(car_of_train(p, p.cars[k]));
    const VehicleStatic alone = car.solve_statics(std::vector<double>(4, 0.0), 9.81);
    for (std::size_t w = 0; w < 4; ++w)
      EXPECT_NEAR(st.contact_force[4 * k + w], alone.contact_force[w],
                  1e-12 * alone.contact_force[w])
          << "car " << k + 1 << " wheel " << w + 1;
  }
  EXPECT_EQ(train.dof_names()[10], "car 2 body z");
}

TEST(TrainModel, ACountWritesOutIdenticalCars) {
  const std::string counted =
      train_text(entry(kPowerCar, 3.2, 3.4) + entry(kTrailer, 2.6, 2.9, "count = 3\n"));
  const std::string written = train_text(entry(kPowerCar, 3.2, 3.4) + entry(kTrailer, 2.6, 2.9) +
                                         entry(kTrailer, 2.6, 2.9) + entry(kTrailer, 2.6, 2.9));
  const VehicleParams a = parse(counted), b = parse(written);
  ASSERT_EQ(a.cars.size(), 4u);
  EXPECT_TRUE(a == b);
  const VehicleModel ma(a), mb(b);
  EXPECT_TRUE(same_bits(ma.stiffness(), mb.stiffness()));
  EXPECT_TRUE(same_bits(ma.damping(), mb.damping()));
  EXPECT_TRUE(same_bits(ma.mass(), mb.mass()));
  EXPECT_EQ(wheel_offsets(a), wheel_offsets(b));
}

void expect_error(const std::string& text, const std::string& fragment) {
  try {
    parse(text);
    ADD_FAILURE() << "no error; expected one with '" << fragment << "'";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("train.toml"), std::string::npos) << e.what();
  }
}

TEST(TrainToml, RefusalsNameTheEntryAndKey) {
  const std::string first = entry(kPowerCar, 3.2, 3.4);
  expect_error(train_text(""), "'vehicle.cars': missing");
  expect_error(train_text("cars = []\n"), "'vehicle.cars': has no entries");
  expect_error(train_text("cars = 3\n"), "'vehicle.cars': must be an array of tables");
  std::string no_mass = entry(kTrailer, 2.6, 2.9);
  no_mass.erase(no_mass.find("body_mass"),
                no_mass.find('\n', no_mass.find("body_mass")) + 1 - no_mass.find("body_mass"));
  expect_error(train_text(first + no_mass), "'vehicle.cars[2].body_mass': missing");
  expect_error(train_text(first + entry(kTrailer, 2.6, 2.9, "count = 0\n")),
               "'vehicle.cars[2].count': must be 1 to 64 cars");
  expect_error(train_text(entry(kPowerCar, 3.2, 3.4, "count = 40\n") +
                          entry(kTrailer, 2.6, 2.9, "count = 25\n")),
               "'vehicle.cars[2].count': brings the train to 65 cars, more than the 64 allowed");
  std::string many;
  for (int i = 0; i < 65; ++i) many += first;
  expect_error(train_text(many), "'vehicle.cars': 65 entries, more than the 64 allowed");
  expect_error(train_text(first + entry(kTrailer, 1.2, 2.9)),
               "'vehicle.cars[2].front_overhang': must be at least wheelset_semi_base = 1.25 m");
  expect_error(train_text(entry(kPowerCar, 3.2, 1.4)),
               "'vehicle.cars[1].rear_overhang': must be at least wheelset_semi_base = 1.5 m");
  expect_error(train_text(first + entry(kTrailer, 2.6, 2.9, "coupler = 1.0\n")),
               "'vehicle.cars[2].coupler': unknown key in an entry of [[vehicle.cars]]");
  std::string wide = entry(kTrailer, 9.0, 9.0);
  wide.replace(wide.find("wheelset_semi_base = 1.25"), 25, "wheelset_semi_base = 8.75");
  expect_error(train_text(first + wide),
               "'vehicle.cars[2].wheelset_semi_base': must be less than bogie_semi_spacing");
  // The car's keys belong in the entries, and a car has no [[vehicle.cars]].
  expect_error(std::string(kHead) + "model = \"train\"\nbody_mass = 1.0\n" + first,
               "'vehicle.body_mass': unknown key for model = \"train\"");
  expect_error(car_text() + first, "'vehicle.cars': unknown key for model = \"car\"");
}

std::string read(const std::string& relative) {
  std::ifstream f(test::source_path(relative));
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// scenes/car_irregular.toml with its [vehicle] table replaced by `vehicle`.
Scene scene_with(const std::string& vehicle) {
  std::string t = read("scenes/car_irregular.toml");
  const auto a = t.find("\n[vehicle]");
  const auto b = t.find("\n[", a + 1);
  t.replace(a + 1, b - a - 1, vehicle + "\n");
  return parse_scene(t, "train.toml");
}

// The scene's wheels and the monolithic matrix's DOF order: one car is the
// car, two cars are numbered car after car in the car's order, and the
// vehicle's band stays as narrow as one car's.
TEST(TrainScene, WheelsAndDofOrderAreTheCarsOneAfterTheOther) {
  const Scene car = scene_with(car_text());
  const Scene one = scene_with(train_text(entry(kPowerCar, 3.2, 3.4)));
  EXPECT_EQ(one.wheel_count(), 4);
  EXPECT_EQ(one.wheel_offsets(), car.wheel_offsets());
  EXPECT_EQ(one.vehicle_mass, car.vehicle_mass);
  const Scene two = scene_with(train_text(entry(kPowerCar, 3.2, 3.4) + entry(kTrailer, 2.6, 2.9)));
  EXPECT_EQ(two.wheel_count(), 8);
  EXPECT_EQ(two.wheel_offsets(), wheel_offsets(two.vehicle));
  ParticipantSpec vehicle_only;
  vehicle_only.parts.add(Component::kVehicle);
  const DofLayout lc = make_layout(car, vehicle_only.parts),
                  l1 = make_layout(one, vehicle_only.parts),
                  l2 = make_layout(two, vehicle_only.parts);
  EXPECT_EQ(l1.vehicle, lc.vehicle);
  EXPECT_EQ(l1.wheels, lc.wheels);
  ASSERT_EQ(l2.vehicle.size(), 20u);
  for (std::size_t i = 0; i < 20; ++i)
    EXPECT_EQ(l2.vehicle[i], 10 * static_cast<int>(i / 10) + lc.vehicle[i % 10]) << i;
  const std::vector<int> wheels = {0, 1, 8, 9, 10, 11, 18, 19};
  EXPECT_EQ(l2.wheels, wheels);
  const Structure sc = assemble(car, vehicle_only), s2 = assemble(two, vehicle_only);
  EXPECT_EQ(s2.K.half_bandwidth(), sc.K.half_bandwidth());
  EXPECT_EQ(sc.K.half_bandwidth(), 3);
}

}  // namespace train_model_test
}  // namespace railcosim
