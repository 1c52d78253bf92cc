// The co-simulation engine against the monolithic reference: consistency
// (convergence as H shrinks) and the paper's findings.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "run/assess.hpp"
#include "run/runner.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace {

using run::assess;
using run::run_cosim;
using run::run_monolithic;
using run::RunOptions;
using run::RunRecord;

RunRecord judged_run(const Scene& scene, const std::string& name, double H, double tol,
                     Feedthrough ft = Feedthrough::kLagged) {
  RunOptions o;
  o.macro_step = H;
  o.tolerance = tol;
  o.feedthrough = ft;
  const RunRecord reference = run_monolithic(scene, o);
  RunRecord r = run_cosim(scene, parse_case(name), o, remote::inproc_factory(scene), "inproc");
  assess(r, reference, scene, parse_case(name), o);
  return r;
}

// Error against H over three halvings: a zero-order hold is first order, so
// the error roughly halves when H halves.
class ConsistencyTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ConsistencyTest, ConvergesToTheMonolithicSolutionAtFirstOrder) {
  Scene scene = test::paper_scene();
  scene.end_time = 0.05;  // a shorter run keeps the finest H cheap
  scene.validate();
  // Integration error far below the coupling error at the finest H.
  const double tol = 1e-10;
  std::vector<double> hs, errs;
  for (double H : {2e-4, 1e-4, 5e-5, 2.5e-5}) {
    const RunRecord r = judged_run(scene, GetParam(), H, tol);
    ASSERT_EQ(r.status, "ok") << r.message;
    hs.push_back(H);
    errs.push_back(*r.rel_l2_error);
  }
  for (std::size_t i = 1; i < errs.size(); ++i) {
    const double ratio = errs[i - 1] / errs[i];
    EXPECT_GT(ratio, 1.5) << "H " << hs[i - 1] << " -> " << hs[i];
    EXPECT_LT(ratio, 2.7) << "H " << hs[i - 1] << " -> " << hs[i];
  }
  EXPECT_NEAR(test::fitted_order(hs, errs), 1.0, 0.25);
}

std::string param_name(const ::testing::TestParamInfo<const char*>& info) {
  std::string n = info.param;
  for (char& ch : n)
    if (ch == '-' || ch == '+' || ch == '@') ch = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(OnePerSplit, ConsistencyTest,
                         ::testing::Values("wr-xx-jacobi", "rs-xx-jacobi", "rs-xt-jacobi"),
                         param_name);

// The same on the soil scene: every one-cut case at the sleepers/soil cut,
// and the three-participant cases vehicle | track | soil.
class SoilConsistencyTest : public ::testing::TestWithParam<const char*> {};

TEST_P(SoilConsistencyTest, ConvergesToTheMonolithicSolutionAtLeastAtFirstOrder) {
  Scene scene = load_scene(test::source_path("scenes/soil.toml"));
  scene.end_time = 0.02;
  scene.validate();
  const double tol = 1e-10;
  // "@resolved": the lagged Jacobi X-T wheel/rail coupling is the amplified
  // case of the paper; its consistent variant reads the force resolved.
  std::string name = GetParam();
  const std::string suffix = "@resolved";
  const bool resolved =
      name.size() > suffix.size() && name.substr(name.size() - suffix.size()) == suffix;
  if (resolved) name.resize(name.size() - suffix.size());
  std::vector<double> hs, errs;
  // X-T at the wheel/rail cut is amplified from H = 2e-4 s on this scene, so
  // the sweep starts at 1e-4 s.
  for (double H : {1e-4, 5e-5, 2.5e-5, 1.25e-5}) {
    const RunRecord r =
        judged_run(scene, name, H, tol, resolved ? Feedthrough::kResolved : Feedthrough::kLagged);
    // X-T at the wheel/rail cut: its map at rest grows slowly at these H
    // (as on the paper scene, rho = 1.002 at 1e-4 s: amplified), the moving
    // run stays accurate; every other case is ok.
    const bool slow = r.status == "amplified" && name.rfind("wr-xt", 0) == 0 && r.spectral_rate &&
                      *r.spectral_rate < 100;
    ASSERT_TRUE(r.status == "ok" || slow) << "H = " << H << ": " << r.message;
    hs.push_back(H);
    errs.push_back(*r.rel_l2_error);
  }
  // A zero-order hold is first order; some Gauss–Seidel cases converge
  // faster (their leading error terms cancel), none slower.
  for (std::size_t i = 1; i < errs.size(); ++i) EXPECT_LT(errs[i], errs[i - 1] / 1.5) << hs[i];
  EXPECT_GT(test::fitted_order(hs, errs), 0.8)
      << "errors " << errs[0] << " " << errs[1] << " " << errs[2] << " " << errs[3];
}

INSTANTIATE_TEST_SUITE_P(SleepersSoilAndThreeParticipants, SoilConsistencyTest,
                         ::testing::Values("ss-xx-jacobi", "ss-xt-jacobi", "ss-xx-gauss-seidel",
                                           "ss-xt-gauss-seidel", "wr-xx+ss-xx-jacobi",
                                           "wr-xx+ss-xt-jacobi", "wr-xt+ss-xx-jacobi@resolved",
                                           "wr-xt+ss-xt-jacobi@resolved",
                                           "wr-xx+ss-xx-gauss-seidel", "wr-xx+ss-xt-gauss-seidel",
                                           "wr-xt+ss-xx-gauss-seidel", "wr-xt+ss-xt-gauss-seidel"),
                         param_name);

// The paper's findings on the paper scene at H = 1e-4 s.
class PaperFindings : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Scene scene = test::paper_scene();
    for (const std::string& n : paper_case_names())
      if (n != "monolithic") runs_[n] = judged_run(scene, n, scene.macro_step, scene.tolerance);
    runs_["wr-xt-jacobi-resolved"] = judged_run(scene, "wr-xt-jacobi", scene.macro_step,
                                                scene.tolerance, Feedthrough::kResolved);
  }
  static const RunRecord& run(const std::string& name) { return runs_.at(name); }
  static inline std::map<std::string, RunRecord> runs_;
};

TEST_F(PaperFindings, LaggedJacobiXTAtTheWheelRailCutIsAmplified) {
  const RunRecord& amplified = run("wr-xt-jacobi");
  EXPECT_EQ(amplified.status, "amplified") << amplified.message;
  for (const auto& [name, r] : runs_) {
    if (name == "wr-xt-jacobi") continue;
    // Its deflection error at t_end is the largest, and over the whole history
    // its error dwarfs every other case's.
    EXPECT_GT(*amplified.rel_l2_error, *r.rel_l2_error) << "against " << name;
    EXPECT_GT(*amplified.history_error, 20.0 * *r.history_error) << "against " << name;
  }
}

// Resolved feedthrough reduces the amplification to a slow growth: its map
// at rest has rho = 1.00217 (e-folds in 46 ms) where lagged Jacobi's has
// 1.101 (in 1 ms); the moving run stays as accurate as Jacobi X-X.
TEST_F(PaperFindings, ResolvedFeedthroughReducesTheAmplification) {
  const RunRecord& resolved = run("wr-xt-jacobi-resolved");
  const RunRecord& lagged = run("wr-xt-jacobi");
  const RunRecord& xx = run("wr-xx-jacobi");
  EXPECT_EQ(resolved.status, "amplified") << resolved.message;
  EXPECT_LT(40.0 * *resolved.spectral_rate, *lagged.spectral_rate);
  // Close to Jacobi X-X: within a factor of two of its error.
  EXPECT_LT(*resolved.rel_l2_error, 2.0 * *xx.rel_l2_error);
  EXPECT_GT(*resolved.rel_l2_error, 0.5 * *xx.rel_l2_error);
}

TEST_F(PaperFindings, GaussSeidelBeatsJacobiAtTheRailSleepersCut) {
  EXPECT_LT(4.0 * *run("rs-xx-gauss-seidel").rel_l2_error, *run("rs-xx-jacobi").rel_l2_error);
}

TEST_F(PaperFindings, XTBeatsXXAtTheRailSleepersCutUnderJacobi) {
  EXPECT_LT(*run("rs-xt-jacobi").rel_l2_error, *run("rs-xx-jacobi").rel_l2_error);
}

// Every other case stays within 10 %; ok but for the two X-T couplings at
// the wheel/rail cut whose maps at rest grow slowly (rho = 1.00199 and
// 1.00217: amplified).
TEST_F(PaperFindings, EveryOtherCaseStaysWithinTenPercent) {
  for (const auto& [name, r] : runs_) {
    if (name == "wr-xt-jacobi") continue;
    const bool slow = name == "wr-xt-gauss-seidel" || name == "wr-xt-jacobi-resolved";
    EXPECT_EQ(r.status, slow ? "amplified" : "ok") << name << ": " << r.message;
    EXPECT_LT(*r.rel_l2_error, 0.10) << name;
  }
}

TEST_F(PaperFindings, EveryRunCoversTheWholeTime) {
  for (const auto& [name, r] : runs_) {
    EXPECT_EQ(r.macro_steps, 2500) << name;
    EXPECT_EQ(r.history.size(), 2501u) << name;
    EXPECT_EQ(r.deflection.size(), 101u) << name;
  }
}

// Reads a CSV of numbers (header skipped) into rows.
std::vector<std::vector<double>> read_csv(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::vector<std::vector<double>> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// The largest difference per column over `rows` rows, relative to the
// column's largest magnitude in the fixture.
double worst_relative_difference(const std::vector<std::vector<double>>& got,
                                 const std::vector<std::vector<double>>& want, std::size_t rows) {
  double worst = 0;
  for (std::size_t c = 0; c < want.front().size(); ++c) {
    double scale = 0, diff = 0;
    for (std::size_t k = 0; k < rows; ++k) {
      scale = std::max(scale, std::abs(want[k][c]));
      diff = std::max(diff, std::abs(got[k][c] - want[k][c]));
    }
    worst = std::max(worst, scale > 0 ? diff / scale : diff);
  }
  return worst;
}

// The engine was rebuilt around components, cuts and statics found through
// the interfaces: every paper case still gives the files it gave before, to
// 1e-9 relative (tests/fixtures/paper: the outputs of the two-subsystem
// engine). The lagged Jacobi X-T wheel/rail case is unstable: it amplifies
// any difference, even one of a few ulps in the static state, by orders of
// magnitude, so it is compared over its first 0.05 s, before the growth
// has reached 1e-9 of the signal.
TEST_F(PaperFindings, EveryCaseReproducesTheFilesOfTheTwoSubsystemEngine) {
  constexpr double kRegressionTolerance = 1e-9;
  for (const auto& [name, r] : runs_) {
    const bool resolved = name == "wr-xt-jacobi-resolved";
    const std::string dir = test::source_path("tests/fixtures/paper/") +
                            (resolved ? "resolved/wr-xt-jacobi" : name) + "/";
    const auto deflection = read_csv(dir + "deflection.csv");
    const auto history = read_csv(dir + "history.csv");
    std::vector<std::vector<double>> got_d, got_h;
    for (std::size_t k = 0; k < r.deflection.size(); ++k)
      got_d.push_back({r.x[k], r.deflection[k]});
    for (const HistoryRow& h : r.history) got_h.push_back({h.t, h.wheel, h.contact_force});
    ASSERT_EQ(got_d.size(), deflection.size()) << name;
    ASSERT_EQ(got_h.size(), history.size()) << name;
    if (name == "wr-xt-jacobi") {
      EXPECT_LT(worst_relative_difference(got_h, history, 501), kRegressionTolerance) << name;
      continue;
    }
    EXPECT_LT(worst_relative_difference(got_d, deflection, deflection.size()), kRegressionTolerance)
        << name;
    EXPECT_LT(worst_relative_difference(got_h, history, history.size()), kRegressionTolerance)
        << name;
  }
}

// The paper's "Gauss–Seidel divides the error of Jacobi by almost 10" at the
// rail/sleepers cut with X-X depends on how a subsystem restarts at a
// communication point. Keeping the integrator's acceleration (carry), with
// 10 fixed micro steps per macro step, gives the paper's ratio (an
// independent reference finds 9.3); restarting from an acceleration
// consistent with the new inputs (this product's default) gives about 32.
TEST(RestartConvention, CarryReproducesThePapersRatioAtTheRailSleepersCut) {
  Scene scene = test::paper_scene();
  scene.micro_steps = 10;
  auto ratio = [&](const std::string& restart) {
    scene.restart = restart;
    const double j = *judged_run(scene, "rs-xx-jacobi", 1e-4, scene.tolerance).rel_l2_error;
    const double gs = *judged_run(scene, "rs-xx-gauss-seidel", 1e-4, scene.tolerance).rel_l2_error;
    return j / gs;
  };
  const double carry = ratio("carry"), consistent = ratio("consistent");
  EXPECT_GE(carry, 5.0);
  EXPECT_LE(carry, 20.0);
  EXPECT_GT(consistent, 25.0);
}

TEST(Divergence, AnUnstableRunStopsEarlyAndSaysWhen) {
  // Lagged Jacobi X-T at the wheel/rail cut with a coarse macro step grows
  // without bound; a tight divergence bound catches it early.
  Scene scene = test::paper_scene();
  scene.divergence_factor = 1.5;
  const RunRecord r = judged_run(scene, "wr-xt-jacobi", 4e-4, scene.tolerance);
  EXPECT_EQ(r.status, "diverged");
  EXPECT_LT(r.macro_steps, 625);
  EXPECT_NE(r.message.find("diverged at macro step " + std::to_string(r.macro_steps)),
            std::string::npos)
      << r.message;
  EXPECT_NE(r.message.find("(t = "), std::string::npos) << r.message;
  EXPECT_FALSE(r.rel_l2_error.has_value());
}

TEST(Divergence, MicroStepsThatRunAwayWhileNothingGrowsEndTheRunAsFailed) {
  // A tolerance no step can meet: the integrator refines until its budget of
  // micro steps per macro step is spent, then gives up instead of grinding.
  // Nothing has grown: the run failed there (not a divergence).
  Scene scene = test::paper_scene();
  scene.end_time = 0.001;
  RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = 1e-30;
  const RunRecord r =
      run_cosim(scene, parse_case("wr-xx-jacobi"), o, remote::inproc_factory(scene), "inproc");
  EXPECT_EQ(r.status, "failed");
  EXPECT_NE(r.message.find("micro steps"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("not judged diverged: the displacements reported until then show no "
                           "growth (largest |u| "),
            std::string::npos)
      << r.message;
  EXPECT_EQ(r.macro_steps, 1);
}

}  // namespace
}  // namespace railcosim
