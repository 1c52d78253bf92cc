// Vehicles and excitation in the engine: the quarter and 10-DOF car on the
// track, their statics through every cut, smooth and excited runs, and four
// wheels over TCP.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>

#include "cosim_support.hpp"
#include "engine/coupled_statics.hpp"
#include "hertz.hpp"
#include "monolithic.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "spectra.hpp"
#include "statics.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace vehicle_engine_test {

using run::run_cosim;
using run::run_monolithic;
using run::RunOptions;
using run::RunRecord;

std::string read(const std::string& relative) {
  std::ifstream f(test::source_path(relative));
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Replaces the table [name] (header to the next table) by `table` ("" drops it).
std::string with_table(std::string text, const std::string& name, const std::string& table) {
  const auto a = text.find("\n[" + name + "]");
  if (a == std::string::npos) return text + "\n" + table;
  auto b = text.find("\n[", a + 1);
  if (b == std::string::npos) b = text.size();
  return text.replace(a + 1, b - a - 1, table);
}

std::string with_key(std::string text, const std::string& key, const std::string& line) {
  const auto a = text.find("\n" + key + " =");
  EXPECT_NE(a, std::string::npos) << key;
  return text.replace(a + 1, text.find('\n', a + 1) - a - 1, line);
}

const std::string kFixedSoil = "[soil]\nmodel = \"fixed\"\n";

// The car of scenes/car_irregular.toml on a smooth rail.
std::string smooth_car(double end_time) {
  std::string t = with_table(read("scenes/car_irregular.toml"), "irregularity", "");
  return with_key(t, "end_time", "end_time = " + std::to_string(end_time));
}

Scene scene_of(const std::string& text) {
  return parse_scene(text, "test.toml");
}

// The global static state of the whole model.
Vector global_statics(const Scene& s, Structure& st) {
  ParticipantSpec whole;
  whole.parts = Parts::all(s);
  st = assemble(s, whole);
  return solve_static(st, Vector::Zero(st.layout.size));
}

// Each model's contact forces add up to its weight, and the suspensions
// carry the closed-form shares: the car is statically determinate, so the
// track under it changes nothing.
TEST(VehicleStatics, ContactForcesCarryTheWeightAndSuspensionsTheirShares) {
  // Direct factorisation and Newton to round-off: 1e-9 of the weight leaves
  // room for the conditioning of the whole track.
  constexpr double kRel = 1e-9;
  for (const char* file : {"scenes/car_irregular.toml", "scenes/wheel_flat.toml"}) {
    const Scene s = scene_of(read(file));
    Structure st;
    const Vector u = global_statics(s, st);
    const VehicleModel v = s.vehicle_model();
    const double weight = v.total_mass() * s.gravity;
    ASSERT_EQ(st.contacts.size(), static_cast<std::size_t>(s.wheel_count())) << file;
    double sum = 0;
    for (const ContactTerm& c : st.contacts) {
      ContactTerm::Entry g[5];
      const int ng = c.entries(0.0, st.layout, g);
      double delta = c.static_delta0(0.0);
      for (int i = 0; i < ng; ++i) delta += g[i].weight * u[g[i].dof];
      const double F = hertz_force(c.hertz_constant, delta);
      EXPECT_NEAR(F, weight / s.wheel_count(), kRel * weight) << file;
      sum += F;
    }
    EXPECT_NEAR(sum, weight, kRel * weight) << file;
    // Suspension compressions from the vehicle DOFs of the global state.
    Eigen::VectorXd q(v.dofs());
    for (int i = 0; i < v.dofs(); ++i) q[i] = u[st.layout.vehicle[static_cast<std::size_t>(i)]];
    const VehicleParams& p = s.vehicle;
    const double g = s.gravity;
    for (const Suspension& susp : v.suspensions()) {
      double want = 0;
      if (p.type == VehicleType::quarter)
        want = susp.name == "secondary" ? p.body_mass * g / p.secondary_stiffness
                                        : (p.body_mass + p.bogie_mass) * g / p.primary_stiffness;
      else
        want = susp.name.rfind("secondary", 0) == 0
                   ? p.body_mass * g / 2 / p.secondary_stiffness
                   : (p.body_mass / 2 + p.bogie_mass) * g / 2 / p.primary_stiffness;
      // Compressions of 1-200 mm; kRel of them.
      EXPECT_NEAR(susp.a.dot(q), want, kRel * want) << file << ": " << susp.name;
    }
  }
}

// Every DOF of every body from the participants of a case, in a fixed order.
std::vector<double> gather(const std::vector<std::unique_ptr<Subsystem>>& subs) {
  std::vector<double> vehicle, rail, sleepers, soil;
  for (const auto& sub : subs) {
    const DofLayout& l = sub->structure().layout;
    const Vector& u = sub->integrator_state().u;
    for (int d : l.vehicle) vehicle.push_back(u[d]);
    for (int d : l.rail_w) rail.push_back(u[d]);
    for (int d : l.sleeper) sleepers.push_back(u[d]);
    for (int d : l.soil) soil.push_back(u[d]);
  }
  for (const auto* v : {&rail, &sleepers, &soil})
    vehicle.insert(vehicle.end(), v->begin(), v->end());
  return vehicle;
}

class CarInterfaceStatics : public ::testing::TestWithParam<const char*> {};

// The coupled static state found through the interfaces (four coupling
// points at the wheel/rail cut) equals the global solution, as for one wheel.
TEST_P(CarInterfaceStatics, EqualsTheGlobalStaticSolution) {
  const Scene s = scene_of(read("scenes/car_irregular.toml"));
  test::InprocCase c = test::inproc_case_at_statics(s, GetParam());
  const std::vector<Participant*>& ps = c.ps;
  const engine::StaticsOutcome& out = c.statics;
  for (std::size_t p = 0; p < ps.size(); ++p) ps[p]->initialize(out.inputs[p]);
  std::vector<std::unique_ptr<Subsystem>> whole;
  Structure st;
  const Vector u = global_statics(s, st);
  std::vector<double> want;
  for (const auto* dofs :
       {&st.layout.vehicle, &st.layout.rail_w, &st.layout.sleeper, &st.layout.soil})
    for (int d : *dofs) want.push_back(u[d]);
  const std::vector<double> got = gather(c.subs);
  ASSERT_EQ(got.size(), want.size());
  double scale = 0, diff = 0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    scale = std::max(scale, std::abs(want[k]));
    diff = std::max(diff, std::abs(got[k] - want[k]));
  }
  // The interface iteration stops at a relative change of 1e-13; 1e-9 as for one wheel.
  EXPECT_LT(diff, 1e-9 * scale) << GetParam() << " after " << out.iterations << " iterations";
}

INSTANTIATE_TEST_SUITE_P(EveryCut, CarInterfaceStatics,
                         ::testing::Values("wr-xx-jacobi", "wr-xt-jacobi", "rs-xx-jacobi",
                                           "ss-xt-jacobi", "wr-xt+ss-xx-jacobi"),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           for (char& ch : n)
                             if (ch == '-' || ch == '+') ch = '_';
                           return n;
                         });

RunOptions options(const Scene& s, double H) {
  RunOptions o;
  o.macro_step = H;
  o.tolerance = s.tolerance;
  return o;
}

// Column `name` of a run's history (contact_force_N, or an extra channel).
std::vector<double> column(const RunRecord& r, const std::string& name) {
  std::vector<double> out;
  for (const HistoryRow& h : r.history) {
    if (name == "contact_force_N") {
      out.push_back(h.contact_force);
      continue;
    }
    for (std::size_t k = 0; k < r.extra_channels.size(); ++k)
      if (r.extra_channels[k] == name) out.push_back(h.extra[k]);
  }
  EXPECT_EQ(out.size(), r.history.size()) << name;
  return out;
}

// The largest relative deviation of any wheel's force from its static load
// over the history rows with t_from <= t < t_to.
double worst_wheel_deviation(const RunRecord& r, double wheel_load, double t_from, double t_to) {
  double worst = 0;
  for (int w = 1; w <= 4; ++w) {
    const std::vector<double> f = column(r, "force_w" + std::to_string(w) + "_N");
    for (std::size_t i = 0; i < f.size(); ++i)
      if (r.history[i].t >= t_from && r.history[i].t < t_to)
        worst = std::max(worst, std::abs(f[i] - wheel_load) / wheel_load);
  }
  return worst;
}

Scene smooth_car_at(double end_time, double speed_kmh) {
  std::string t = with_table(smooth_car(end_time), "soil", kFixedSoil);
  return scene_of(with_key(t, "speed_kmh", "speed_kmh = " + std::to_string(speed_kmh)));
}

// On a smooth rail the car's wheels keep their static loads: what varies is
// the sleeper-passing modulation of the track's stiffness (0.6 % here) once
// the start has settled. The first 15 ms are left out: the run starts from
// the static state of the car standing still (the model's convention: every
// velocity zero), not from the steady state of a load moving at v, whose
// track moves with the convected velocity -v du/dx and whose trailing wheels
// sit on the slope of the rail bent by the wheel ahead. The start therefore
// sets off a transient of 2 % at 160 km/h that decays below 1 % within 10 ms
// (the next test shows it is the speed's doing).
TEST(CarRun, SmoothTrackKeepsEveryContactForceWithinOnePercentOfStatic) {
  const Scene s = smooth_car_at(0.06, 160.0);
  const RunRecord r = run_monolithic(s, options(s, s.macro_step));
  const double wheel_load = s.vehicle_model().total_mass() * s.gravity / 4;
  for (int w = 1; w <= 4; ++w)  // the static state
    EXPECT_NEAR(column(r, "force_w" + std::to_string(w) + "_N").front(), wheel_load,
                1e-9 * wheel_load);
  const double worst = worst_wheel_deviation(r, wheel_load, 0.015, 1.0);
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(worst, 1e-4);  // the wheels do feel the sleepers
}

// The start-up transient left out above is a velocity effect, not an error
// of the static state: it grows in proportion to the speed (a wrong static
// state would disturb the wheels as much at any speed).
TEST(CarRun, StartUpTransientGrowsInProportionToTheSpeed) {
  std::vector<double> peak;
  for (double kmh : {16.0, 160.0}) {
    const Scene s = smooth_car_at(0.015, kmh);
    const RunRecord r = run_monolithic(s, options(s, s.macro_step));
    peak.push_back(
        worst_wheel_deviation(r, s.vehicle_model().total_mass() * s.gravity / 4, 0.0, 1.0));
  }
  // Measured 0.19 % and 2.05 %: a ratio of 10.8 for a speed ratio of 10. The
  // terms of second order in v (the track's inertia, the lag of the bent
  // rail behind a damped moving load) and the sleeper-passing modulation
  // make it not exactly 10; 15 % allows them, while a speed-independent
  // disturbance of 0.06 % of the wheel load would already take it below 8.5.
  EXPECT_NEAR(peak[1] / peak[0], 10.0, 1.5) << peak[0] << " " << peak[1];
  EXPECT_GT(peak[1], 0.01);  // the transient the test above leaves out
  EXPECT_LT(peak[1], 0.03);
}

// The car's run converges as the tolerance tightens, down to 1e-10 m. The
// body hangs 0.17 m down on its springs: an integrator that solved each
// step for the displacement itself, not for its change from the start,
// would round that 0.17 m into the body's acceleration over beta h^2 and
// stall at a relative error of 1e-6 whatever the tolerance (measured: 1.4,
// 1.0, 0.99, 1.1e-6 at 1e-7 ... 1e-10 m).
TEST(CarRun, DeflectionSelfConvergesAsTheToleranceTightens) {
  const Scene s = smooth_car_at(0.06, 160.0);
  RunOptions o = options(s, s.macro_step);
  o.tolerance = 1e-11;
  const RunRecord reference = run_monolithic(s, o);
  std::vector<double> errs;
  for (double tol : {1e-8, 1e-9, 1e-10}) {
    o.tolerance = tol;
    errs.push_back(
        verdict::deflection_error(run_monolithic(s, o).deflection, reference.deflection).rel_l2);
  }
  // Measured 2.5e-7, 1.3e-7, 6.8e-8: a factor 1.9 per decade of tolerance;
  // 1.5 leaves room for the step-size pattern, which changes with it.
  for (std::size_t i = 1; i < errs.size(); ++i)
    EXPECT_GT(errs[i - 1] / errs[i], 1.5) << "tolerance 1e-" << 8 + i;
  EXPECT_LT(errs.back(), 2e-7);
}

// The dominant frequency of a signal: the largest DFT line above f_min.
double peak_frequency(const std::vector<double>& x, double dt, double f_min) {
  std::size_t n = 1;
  while (n < x.size()) n <<= 1;
  double mean = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  std::vector<std::complex<double>> X(n, 0.0);
  for (std::size_t i = 0; i < x.size(); ++i) X[i] = x[i] - mean;
  fft(X);
  const double df = 1.0 / (static_cast<double>(n) * dt);
  std::size_t best = 0;
  for (std::size_t k = 1; k <= n / 2; ++k)
    if (static_cast<double>(k) * df >= f_min && (best == 0 || std::abs(X[k]) > std::abs(X[best])))
      best = k;
  return static_cast<double>(best) * df;
}

// A sinusoidal rail profile of wavelength lambda excites the contact force
// at v / lambda: the peak of its spectrum, and the loudest third-octave band.
TEST(CarRun, SinusoidalProfileExcitesTheContactForceAtSpeedOverWavelength) {
  // 99 Hz at 100 km/h, mid-band of the 100 Hz band and away from the 46 Hz
  // sleeper passing.
  const double lambda = 0.28;
  std::string t = with_table(read("scenes/wheel_flat.toml"), "wheel_flat", "");
  t = with_table(t, "irregularity",
                 "[irregularity]\nmodel = \"sine\"\namplitude = 20e-6\nwavelength = 0.28\n");
  t = with_key(t, "end_time", "end_time = 0.2");
  const Scene s = scene_of(t);
  const RunRecord r = run_monolithic(s, options(s, s.macro_step));
  const std::vector<double> f = column(r, "contact_force_N");
  const double expected = s.speed / lambda;
  // Zero-padded to 4096 lines over 0.41 s: a line every 2.4 Hz.
  EXPECT_NEAR(peak_frequency(f, s.macro_step, 20.0), expected, 2.5);
  const auto bands = third_octave_spectrum(f, s.macro_step, 20.0, 1000.0);
  const Band* loudest = &bands.front();
  for (const Band& b : bands)
    if (b.rms > loudest->rms) loudest = &b;
  EXPECT_EQ(loudest->index, third_octave_index(expected));
}

// A wheel flat strikes once per revolution: force peaks pi D / v apart.
TEST(CarRun, WheelFlatGivesOneForcePeakPerRevolution) {
  const Scene s = scene_of(read("scenes/wheel_flat.toml"));
  const RunRecord r = run_monolithic(s, options(s, s.macro_step));
  const std::vector<double> f = column(r, "contact_force_N");
  const double static_load = s.vehicle_model().total_mass() * s.gravity;
  // An impact: a local maximum above 1.5 times the static load, the largest
  // within half a revolution around it.
  const double period = std::numbers::pi * s.wheel_flat->diameter / s.speed;
  const auto half = static_cast<std::ptrdiff_t>(0.5 * period / s.macro_step);
  std::vector<double> peaks;
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(f.size()); ++i) {
    if (f[static_cast<std::size_t>(i)] < 1.5 * static_load) continue;
    bool top = true;
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, i - half);
         j < std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(f.size()), i + half); ++j)
      top = top && f[static_cast<std::size_t>(j)] <= f[static_cast<std::size_t>(i)];
    if (top) peaks.push_back(r.history[static_cast<std::size_t>(i)].t);
  }
  const double first = s.wheel_flat->angle * s.wheel_flat->diameter / 2 / s.speed;
  const auto revolutions = static_cast<std::size_t>((s.end_time - first) / period) + 1;
  ASSERT_EQ(peaks.size(), revolutions);
  // The peak follows the flat's centre by a fraction of the flat's length
  // (L / v = 1.8 ms); successive peaks repeat to an output step.
  EXPECT_NEAR(peaks.front(), first, s.wheel_flat->length / s.speed);
  for (std::size_t k = 1; k < peaks.size(); ++k)
    EXPECT_NEAR(peaks[k] - peaks[k - 1], period, 1.5 * s.macro_step);
}

// The co-simulation of the car converges to its monolithic solution as H shrinks.
TEST(CarCosim, ConvergesToTheMonolithicSolutionAsTheMacroStepShrinks) {
  std::string t = with_table(smooth_car(0.02), "irregularity",
                             "[irregularity]\nmodel = \"sine\"\namplitude = 50e-6\n"
                             "wavelength = 0.5\n");
  const Scene s = scene_of(t);
  for (const char* name : {"wr-xx-gauss-seidel", "rs-xx-jacobi", "wr-xx+ss-xx-jacobi"}) {
    std::vector<double> errs;
    for (double H : {2e-4, 1e-4, 5e-5}) {
      const RunOptions o = options(s, H);
      const RunRecord ref = run_monolithic(s, o);
      RunRecord r = run_cosim(s, parse_case(name), o, remote::inproc_factory(s), "inproc");
      verdict::judge(r, ref, s);
      ASSERT_EQ(r.status, "ok") << name << " H " << H << ": " << r.message;
      errs.push_back(*r.history_error);
    }
    // A zero-order hold is first order: each halving of H at least 1.5 times smaller.
    for (std::size_t i = 1; i < errs.size(); ++i)
      EXPECT_GT(errs[i - 1] / errs[i], 1.5) << name << " step " << i;
  }
}

// Four wheels through the wheel/rail cut over TCP give the very bits of the
// same run in process.
TEST(CarCosim, FourWheelsOverTcpAreBitwiseEqualToInProcess) {
  std::string t = with_table(smooth_car(0.01), "soil", kFixedSoil);
  t = with_table(t, "irregularity",
                 "[irregularity]\nmodel = \"random\"\nfra_class = 6\nwavelength_min = 1.524\n"
                 "wavelength_max = 30.0\nseed = 7\ncomponents = 256\n");
  const Scene s = scene_of(t);
  remote::NodePool pool;
  const remote::SceneTransport tcp = remote::tcp_transport(s, {}, pool);
  for (const char* name : {"wr-xx-jacobi", "wr-xt-gauss-seidel"}) {
    const RunOptions o = options(s, s.macro_step);
    const RunRecord local = run_cosim(s, parse_case(name), o, remote::inproc_factory(s), "inproc");
    const RunRecord remote = run_cosim(s, parse_case(name), o, tcp.factory, "tcp");
    ASSERT_EQ(remote.status, "ok") << remote.message;
    ASSERT_EQ(local.status, "ok") << local.message;
    EXPECT_EQ(remote.deflection, local.deflection) << name;
    EXPECT_EQ(remote.extra_channels, local.extra_channels);
    ASSERT_EQ(remote.history.size(), local.history.size());
    for (std::size_t i = 0; i < local.history.size(); ++i) {
      EXPECT_EQ(remote.history[i].contact_force, local.history[i].contact_force) << i;
      EXPECT_EQ(remote.history[i].extra, local.history[i].extra) << i;
    }
    EXPECT_EQ(remote.micro_steps, local.micro_steps);
  }
}

}  // namespace vehicle_engine_test
}  // namespace railcosim
