// The co-simulation engine against the monolithic reference: consistency
// (convergence as H shrinks) and the paper's findings.
#include <gtest/gtest.h>

#include <map>

#include "evaluation.hpp"
#include "runner.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

RunRecord judged_run(const Scene& scene, const std::string& name, double H, double tol,
                     Feedthrough ft = Feedthrough::kLagged) {
  RunOptions o;
  o.macro_step = H;
  o.tolerance = tol;
  o.feedthrough = ft;
  const RunRecord reference = run_monolithic(scene, o);
  RunRecord r = run_cosim(scene, parse_case(name), o, inproc_factory(scene), "inproc");
  judge(r, reference, scene);
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

INSTANTIATE_TEST_SUITE_P(OnePerSplit, ConsistencyTest,
                         ::testing::Values("wr-xx-jacobi", "rs-xx-jacobi", "rs-xt-jacobi"),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

// The paper's findings on the paper scene at H = 1e-4 s.
class PaperFindings : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Scene scene = test::paper_scene();
    for (const char* const* n = all_case_names() + 1; *n; ++n)
      runs_[*n] = judged_run(scene, *n, scene.macro_step, scene.tolerance);
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

TEST_F(PaperFindings, ResolvedFeedthroughRemovesTheAmplification) {
  const RunRecord& resolved = run("wr-xt-jacobi-resolved");
  const RunRecord& xx = run("wr-xx-jacobi");
  EXPECT_EQ(resolved.status, "ok") << resolved.message;
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

TEST_F(PaperFindings, EveryOtherCaseStaysWithinTenPercent) {
  for (const auto& [name, r] : runs_) {
    if (name == "wr-xt-jacobi") continue;
    EXPECT_EQ(r.status, "ok") << name << ": " << r.message;
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

TEST(Divergence, MicroStepsThatRunAwayEndTheRunAsDiverged) {
  // A tolerance no step can meet: the integrator refines until its budget of
  // micro steps per macro step is spent, then gives up instead of grinding.
  Scene scene = test::paper_scene();
  scene.end_time = 0.001;
  RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = 1e-30;
  const RunRecord r =
      run_cosim(scene, parse_case("wr-xx-jacobi"), o, inproc_factory(scene), "inproc");
  EXPECT_EQ(r.status, "diverged");
  EXPECT_NE(r.message.find("micro steps"), std::string::npos) << r.message;
  EXPECT_EQ(r.macro_steps, 1);
}

}  // namespace
}  // namespace railcosim
