// The train in whole runs: the two-car scene tests/train_scene.toml run as a
// user runs it (master run, monolithic and co-simulated with each
// participant a node process over TCP), and its co-simulation against the
// monolithic solution as the macro step shrinks, as the car's is
// (vehicle_engine_test).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cosim_case.hpp"
#include "cosim_support.hpp"
#include "process_support.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "statics.hpp"
#include "test_support.hpp"
#include "track_model.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace train_run_test {

namespace fs = std::filesystem;

const double kG = 9.81;  // the scene's gravity

std::string scene_path() {
  return test::source_path("tests/train_scene.toml");
}

// Each wheel's static load: a car is symmetric (bogies alike, the body's
// centre midway), so its four wheels carry a quarter of its mass each.
std::vector<double> wheel_loads(const Scene& s) {
  std::vector<double> loads;
  for (const CarParams& c : s.vehicle.cars)
    for (int w = 0; w < 4; ++w)
      loads.push_back((c.body_mass + 2 * c.bogie_mass + 4 * c.wheelset_mass) * kG / 4);
  return loads;
}

// The columns of a history.csv by name.
std::map<std::string, std::vector<double>> read_history(const fs::path& file) {
  std::istringstream in(test::read_file(file));
  std::string line;
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> columns;
  std::getline(in, line);
  std::istringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::size_t k = 0;
    for (std::string cell; std::getline(row, cell, ',') && k < names.size(); ++k)
      columns[names[k]].push_back(std::stod(cell));
  }
  return columns;
}

std::string force(std::size_t wheel) {
  return "force_w" + std::to_string(wheel + 1) + "_N";
}

// Monolithic, and wr-xx-gauss-seidel with the vehicle and the track each in
// a node process of its own: both finish ok with every wheel's force in the
// history, each car's weight on its own wheels at the start, and the run
// over TCP writes the very bytes of the same run in process.
TEST(TrainRun, MonolithicAndTcpCosimulationFinishOkWithEveryWheel) {
  const Scene s = load_scene(scene_path());
  const std::vector<double> loads = wheel_loads(s);
  ASSERT_EQ(loads.size(), 8u);
  const fs::path out = test::temp_dir("train_run_cli");
  const std::string cosim = " --case wr-xx-gauss-seidel --transport ";
  for (const std::string& args : {" --case monolithic --out " + (out / "mono").string(),
                                  cosim + "tcp --out " + (out / "tcp").string(),
                                  cosim + "inproc --out " + (out / "inproc").string()}) {
    const test::Outcome o = test::run_master("run --scene " + scene_path() + args);
    ASSERT_EQ(o.status, 0) << args << "\n" << o.output;
  }
  const fs::path tcp = out / "tcp" / "wr-xx-gauss-seidel";
  const std::string summary = test::read_file(tcp / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"ok\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"transport\": \"tcp\""), std::string::npos) << summary;
  const std::string history = test::read_file(tcp / "history.csv");
  EXPECT_EQ(history, test::read_file(out / "inproc" / "wr-xx-gauss-seidel" / "history.csv"));
  auto mono = read_history(out / "mono" / "monolithic" / "history.csv");
  auto co = read_history(tcp / "history.csv");
  EXPECT_EQ(mono.count(force(8)), 0u);  // eight wheels, no ninth
  ASSERT_EQ(mono["t_s"].size(), 501u);
  ASSERT_EQ(co["t_s"].size(), 501u);
  for (std::size_t w = 0; w < loads.size(); ++w) {
    ASSERT_EQ(mono[force(w)].size(), 501u) << force(w);
    ASSERT_EQ(co[force(w)].size(), 501u) << force(w);
    // The static state through the whole track (measured: 3e-9 of the load
    // at most) and through the cut's iteration (1e-10).
    EXPECT_NEAR(mono[force(w)].front(), loads[w], 1e-8 * loads[w]) << force(w);
    EXPECT_NEAR(co[force(w)].front(), loads[w], 1e-8 * loads[w]) << force(w);
  }
  fs::remove_all(out);
}

// Column `name` of a run's history (an extra channel).
std::vector<double> column(const run::RunRecord& r, const std::string& name) {
  std::vector<double> out;
  for (const HistoryRow& h : r.history)
    for (std::size_t k = 0; k < r.extra_channels.size(); ++k)
      if (r.extra_channels[k] == name) out.push_back(h.extra[k]);
  EXPECT_EQ(out.size(), r.history.size()) << name;
  return out;
}

// The largest RMS difference of any wheel's force between two runs,
// relative to that wheel's static load.
double wheel_force_error(const run::RunRecord& a, const run::RunRecord& b,
                         const std::vector<double>& loads) {
  double worst = 0;
  for (std::size_t w = 0; w < loads.size(); ++w) {
    const std::vector<double> fa = column(a, force(w)), fb = column(b, force(w));
    double sum = 0;
    for (std::size_t i = 0; i < fa.size() && i < fb.size(); ++i)
      sum += (fa[i] - fb[i]) * (fa[i] - fb[i]);
    worst = std::max(worst, std::sqrt(sum / static_cast<double>(fa.size())) / loads[w]);
  }
  return worst;
}

// The co-simulation of the train converges to its monolithic solution as
// H shrinks, wheel by wheel, as the car's does.
TEST(TrainCosim, EveryWheelConvergesToTheMonolithicSolutionAsTheMacroStepShrinks) {
  const Scene s = load_scene(scene_path());
  const std::vector<double> loads = wheel_loads(s);
  for (const char* name : {"wr-xx-gauss-seidel", "rs-xx-jacobi"}) {
    std::vector<double> errs;
    for (double H : {2e-4, 1e-4, 5e-5}) {
      run::RunOptions o;
      o.macro_step = H;
      o.tolerance = s.tolerance;
      const run::RunRecord ref = run::run_monolithic(s, o);
      run::RunRecord r =
          run::run_cosim(s, parse_case(name), o, remote::inproc_factory(s), "inproc");
      verdict::judge(r, ref, s);
      ASSERT_EQ(r.status, "ok") << name << " H " << H << ": " << r.message;
      errs.push_back(wheel_force_error(r, ref, loads));
    }
    // A zero-order hold is first order: each halving of H at least 1.5 times
    // smaller. Measured (RMS over the run, of the wheel load): 6.5, 3.3, 1.7 %
    // (wr-xx-gauss-seidel) and 2.1, 1.2, 0.62 % (rs-xx-jacobi), ratios 1.8 to 2.0.
    for (std::size_t i = 1; i < errs.size(); ++i)
      EXPECT_GT(errs[i - 1] / errs[i], 1.5)
          << name << " step " << i << ": " << errs[i - 1] << " then " << errs[i];
  }
}

// The coupled static state found through the interfaces (eight coupling
// points at the wheel/rail cut, or the track's cuts under eight wheels)
// equals the global static solution, as for the car.
class TrainInterfaceStatics : public ::testing::TestWithParam<const char*> {};

TEST_P(TrainInterfaceStatics, EqualsTheGlobalStaticSolution) {
  const Scene s = load_scene(scene_path());
  test::InprocCase c = test::inproc_case_at_statics(s, GetParam());
  for (std::size_t p = 0; p < c.ps.size(); ++p) c.ps[p]->initialize(c.statics.inputs[p]);
  ParticipantSpec whole;
  whole.parts = Parts::all(s);
  const Structure st = assemble(s, whole);
  const Vector u = solve_static(st, Vector::Zero(st.layout.size));
  std::vector<double> want, got;
  for (const auto* dofs : {&st.layout.vehicle, &st.layout.rail_w, &st.layout.sleeper})
    for (int d : *dofs) want.push_back(u[d]);
  std::vector<double> rail, sleepers;
  for (const auto& sub : c.subs) {
    const DofLayout& l = sub->structure().layout;
    const Vector& v = sub->integrator_state().u;
    for (int d : l.vehicle) got.push_back(v[d]);
    for (int d : l.rail_w) rail.push_back(v[d]);
    for (int d : l.sleeper) sleepers.push_back(v[d]);
  }
  got.insert(got.end(), rail.begin(), rail.end());
  got.insert(got.end(), sleepers.begin(), sleepers.end());
  ASSERT_EQ(got.size(), want.size());
  double scale = 0, diff = 0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    scale = std::max(scale, std::abs(want[k]));
    diff = std::max(diff, std::abs(got[k] - want[k]));
  }
  // The interface iteration stops at a relative change of 1e-13; 1e-9 as for the car.
  EXPECT_LT(diff, 1e-9 * scale) << GetParam() << " after " << c.statics.iterations << " iterations";
}

INSTANTIATE_TEST_SUITE_P(EveryCut, TrainInterfaceStatics,
                         ::testing::Values("wr-xx-jacobi", "wr-xt-jacobi", "rs-xx-jacobi"),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

}  // namespace train_run_test
}  // namespace railcosim
