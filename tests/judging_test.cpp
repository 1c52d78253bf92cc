// How a run is judged: every coupling quantity's history counts, a large
// deflection error is never ok, and the report's conclusions give the
// paper's number, ours and the tolerance.
#include <gtest/gtest.h>

#include "run/assess.hpp"
#include "run/runner.hpp"
#include "study/report.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace judging_test {

using run::assess;
using run::run_cosim;
using run::run_monolithic;
using run::RunOptions;
using run::RunRecord;
using verdict::judge;
using verdict::kMaxDeflectionError;

RunOptions at(double H, const Scene& s) {
  RunOptions o;
  o.macro_step = H;
  o.tolerance = s.tolerance;
  return o;
}

RunRecord judged_run(const Scene& scene, const char* name, double H) {
  const RunRecord ref = run_monolithic(scene, at(H, scene));
  RunRecord r =
      run_cosim(scene, parse_case(name), at(H, scene), remote::inproc_factory(scene), "inproc");
  assess(r, ref, scene, parse_case(name), at(H, scene));
  return r;
}

// rs-xt-gauss-seidel at H = 5e-4 s: the wheel's history is close to the
// monolithic one, the deflection 178 % off. It was reported ok; it is not
// ok, inaccurate or amplified as its stability says.
TEST(Judging, ALargeDeflectionErrorIsNeverOk) {
  const Scene scene = test::paper_scene();
  const RunRecord r = judged_run(scene, "rs-xt-gauss-seidel", 5e-4);
  ASSERT_TRUE(r.rel_l2_error.has_value());
  EXPECT_GT(*r.rel_l2_error, kMaxDeflectionError);
  EXPECT_EQ(r.status, r.stability == "unstable" ? "amplified" : "inaccurate") << r.message;
  EXPECT_NE(r.message.find("deflection error"), std::string::npos) << r.message;
}

// The consistent cases at the paper's H stay ok (their rel. L2 errors reach
// 4.3e-2), and lagged Jacobi X-T at the wheel/rail cut stays amplified.
// Gauss-Seidel X-T at the wheel/rail cut is as accurate but its map at rest
// grows slowly (rho = 1.00199, 19.9 1/s): amplified, where the probe, blind
// below about 100 1/s, called it ok.
TEST(Judging, ThePaperCasesKeepTheirVerdicts) {
  const Scene scene = test::paper_scene();
  for (const char* name :
       {"wr-xx-jacobi", "wr-xx-gauss-seidel", "wr-xt-gauss-seidel", "rs-xx-jacobi",
        "rs-xx-gauss-seidel", "rs-xt-jacobi", "rs-xt-gauss-seidel"}) {
    const RunRecord r = judged_run(scene, name, scene.macro_step);
    const bool slow = std::string(name) == "wr-xt-gauss-seidel";
    EXPECT_EQ(r.status, slow ? "amplified" : "ok") << name << ": " << r.message;
    EXPECT_LE(*r.rel_l2_error, 4.3e-2) << name;
  }
  EXPECT_EQ(judged_run(scene, "wr-xt-jacobi", scene.macro_step).status, "amplified");
}

// A run whose wheel follows the reference exactly but whose sleepers (the
// rs cut's lower side) or soil channel swing 50 % off is not ok: the
// history error counts every coupling quantity (it counted the wheel's only).
TEST(Judging, EveryCouplingQuantityCounts) {
  const Scene scene = test::paper_scene();
  RunRecord ref, run;
  for (int i = 0; i < 100; ++i) {
    HistoryRow row;
    row.t = i * 1e-4;
    row.wheel = 2e-3;
    row.contact_force = scene.load();
    row.extra = {1e-4};
    ref.history.push_back(row);
    run.history.push_back(row);
    ref.coupling_history["rs"].push_back(1e-3);
    run.coupling_history["rs"].push_back(1e-3);
  }
  ref.extra_channels = run.extra_channels = {"soil_peak_m"};
  ref.deflection = run.deflection = std::vector<double>(101, 1e-3);
  {
    RunRecord r = run;
    judge(r, ref, scene);
    EXPECT_EQ(r.status, "ok");
    EXPECT_EQ(*r.history_error, 0.0);
  }
  {
    RunRecord r = run;
    for (std::size_t i = 1; i < r.coupling_history["rs"].size(); i += 2)
      r.coupling_history["rs"][i] = 1.5e-3;
    judge(r, ref, scene);  // not probed: the size alone makes it inaccurate
    EXPECT_EQ(r.status, "inaccurate");
    // Half the rows 0.5 off, relative to the static value: RMS sqrt(0.125).
    EXPECT_NEAR(*r.history_error, std::sqrt(0.125), 1e-12);
  }
  {
    RunRecord r = run;
    for (std::size_t i = 1; i < r.history.size(); i += 2) r.history[i].extra[0] = 1.5e-4;
    judge(r, ref, scene);
    EXPECT_EQ(r.status, "inaccurate");
    r.stability = "unstable";  // the same sizes with a growing probe: amplified
    r.error_growth = 1e9;
    r.error_growth_rate = 400;
    r.probe_time = 0.05;
    judge(r, ref, scene);
    EXPECT_EQ(r.status, "amplified");
  }
}

// The Gauss–Seidel gain at the rail/sleepers cut is "almost 10" in the
// paper: a gain of 32 is reported as what it is, with the paper's number,
// ours and the tolerance.
TEST(Judging, AGainFarFromTenIsNotReproduced) {
  std::vector<study::StudyRun> runs;
  for (const study::Method& m : study::all_methods()) {
    study::StudyRun s;
    s.group = "case";
    s.method = m.label();
    s.record.case_name = m.spec.name();
    s.record.status = "ok";
    s.record.rel_l2_error = 1e-3;
    s.record.history_error = 1e-3;
    runs.push_back(s);
  }
  for (study::StudyRun& s : runs) {
    if (s.method == "rs-xx-jacobi") s.record.rel_l2_error = 3.2e-2;
    if (s.method == "rs-xx-gauss-seidel") s.record.rel_l2_error = 1e-3;
  }
  bool seen = false;
  for (const study::Finding& f : study::check_findings(runs)) {
    EXPECT_FALSE(f.paper.empty()) << f.claim;
    EXPECT_FALSE(f.judged.empty()) << f.claim;
    if (f.claim.find("by almost 10") == std::string::npos) continue;
    seen = true;
    EXPECT_EQ(f.verdict, "partly reproduced") << f.evidence;
    EXPECT_EQ(f.paper, "almost 10");
    EXPECT_NE(f.evidence.find("ratio 3.2e+01"), std::string::npos) << f.evidence;
    EXPECT_NE(f.evidence.find("not by almost 10"), std::string::npos) << f.evidence;
  }
  EXPECT_TRUE(seen);
}

}  // namespace judging_test
}  // namespace railcosim
