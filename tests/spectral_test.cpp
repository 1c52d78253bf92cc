// Stability as a number: the spectral radius rho of the macro-step map at
// rest (run/spectral.hpp), held against an independent linearisation of the
// paper scene's macro step (vehicle parked, Hertz contact linearised, the
// product's restart and feedthrough, one micro step per macro step), and
// the check over the moving run (the growth of the coupling's defect).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "remote/transport.hpp"
#include "run/execute.hpp"
#include "run/runner.hpp"
#include "run/spectral.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/stability.hpp"

namespace railcosim {
namespace {

using run::RunOptions;
using run::RunRecord;

struct Known {
  const char* name;
  Feedthrough feedthrough;
  double H;
  double rho;  // the independent computation's spectral radius
};

// The six runs the probe called stable (ok or inaccurate) that the
// independent computation finds unstable at rest.
constexpr Known kSix[] = {
    {"wr-xt-gauss-seidel", Feedthrough::kLagged, 5e-5, 1.0000229},
    {"wr-xt-jacobi", Feedthrough::kResolved, 5e-5, 1.0000229},
    {"wr-xt-gauss-seidel", Feedthrough::kLagged, 1e-4, 1.00199},
    {"wr-xt-jacobi", Feedthrough::kResolved, 1e-4, 1.00217},
    {"rs-xt-gauss-seidel", Feedthrough::kLagged, 5e-4, 1.0113},
    {"rs-xx-jacobi", Feedthrough::kLagged, 1e-3, 1.055},
};

std::string label(const Known& k) {
  std::ostringstream s;
  s << k.name << (k.feedthrough == Feedthrough::kResolved ? " resolved" : "") << " H = " << k.H;
  return s.str();
}

RunOptions options_of(const Scene& scene, Feedthrough f, double H) {
  RunOptions o;
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  o.feedthrough = f;
  return o;
}

// The run as `master run` makes it (execute()), over `transport`; its
// summary.json's text in `summary`.
RunRecord executed(const Scene& scene, const char* name, Feedthrough f, double H,
                   const std::string& transport, remote::NodePool* pool, std::string* summary) {
  static std::map<double, RunRecord> references;
  const RunOptions o = options_of(scene, f, H);
  if (!references.count(H)) references[H] = run::run_monolithic(scene, o);
  run::RunJob job;
  job.scene = &scene;
  job.spec = parse_case(name);
  job.options = o;
  job.transport = transport;
  job.nodes.pool = pool;
  // A folder of this run's own: the tests run side by side in processes of their own.
  job.out = std::filesystem::temp_directory_path() /
            ("railcosim_spectral_test-" + std::string(name) + "-" + transport);
  job.folder = std::string(name) + "-" + transport;
  job.reference = [H]() -> const RunRecord& { return references.at(H); };
  const run::RunOutcome out = run::execute(job);
  EXPECT_EQ(out.error, "") << name;
  std::ifstream in(out.dir / "summary.json");
  std::stringstream text;
  text << in.rdbuf();
  if (summary) *summary = text.str();
  std::filesystem::remove_all(job.out);
  return out.record;
}

void expect_unstable_at(const RunRecord& r, const Known& k, const std::string& summary) {
  const double rate = std::log(k.rho) / k.H;
  ASSERT_TRUE(r.spectral_rate.has_value()) << label(k) << ": " << r.message;
  EXPECT_NEAR(*r.spectral_rate, rate, 0.1 * rate) << label(k);
  EXPECT_EQ(r.stability, "unstable") << label(k);
  EXPECT_EQ(r.status, "amplified") << label(k) << ": " << r.message;
  EXPECT_NE(r.message.find("unstable at rest: ρ = "), std::string::npos) << r.message;
  EXPECT_NE(summary.find("\"rho\": "), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"rho_rate_per_s\": "), std::string::npos) << summary;
}

TEST(MacroStepMap, TheSixDisagreementsAreUnstableAtTheirRateInProcess) {
  const Scene scene = test::paper_scene();
  for (const Known& k : kSix) {
    std::string summary;
    const RunRecord r = executed(scene, k.name, k.feedthrough, k.H, "inproc", nullptr, &summary);
    expect_unstable_at(r, k, summary);
  }
}

TEST(MacroStepMap, TheSixDisagreementsAreUnstableAtTheirRateOverTcp) {
  const Scene scene = test::paper_scene();
  remote::NodePool pool;
  for (const Known& k : kSix) {
    std::string summary;
    const RunRecord r = executed(scene, k.name, k.feedthrough, k.H, "tcp", &pool, &summary);
    EXPECT_EQ(r.transport, "tcp");
    expect_unstable_at(r, k, summary);
  }
}

// The strongest instabilities of the sweep: rho about 6, the wheel leaves
// the rail within a few macro steps; the message says the number, never
// that a perturbation "grew only" a little.
TEST(MacroStepMap, TheStrongestTwoSayRhoAboutSix) {
  const Scene scene = test::paper_scene();
  for (const Known& k : {Known{"wr-xt-jacobi", Feedthrough::kResolved, 1e-3, 6.21},
                         Known{"wr-xt-gauss-seidel", Feedthrough::kLagged, 1e-3, 5.88}}) {
    const RunRecord r = executed(scene, k.name, k.feedthrough, k.H, "inproc", nullptr, nullptr);
    ASSERT_TRUE(r.spectral_radius.has_value()) << label(k);
    EXPECT_NEAR(*r.spectral_radius, k.rho, 0.05 * k.rho) << label(k);
    EXPECT_EQ(r.status, "amplified") << label(k);
    // "unstable at rest: ρ = 6.214 per macro step, ...": the number first.
    const std::string rho = "unstable at rest: ρ = " + verdict::rho_words(*r.spectral_radius) + " ";
    EXPECT_EQ(r.message.rfind(rho, 0), 0U) << rho << " in " << r.message;
    EXPECT_EQ(rho.find(std::to_string(k.rho).substr(0, 3)), rho.find("= ") + 2) << rho;
    EXPECT_EQ(r.message.find("grew only"), std::string::npos) << r.message;
  }
}

// Stable couplings of the sweep stay below 1 (lightly damped track modes
// sit just inside the unit circle).
TEST(MacroStepMap, StableCouplingsStayInsideTheUnitCircle) {
  const Scene scene = test::paper_scene();
  for (const Known& k : {Known{"wr-xt-gauss-seidel", Feedthrough::kLagged, 2e-5, 0.99999972},
                         Known{"rs-xx-gauss-seidel", Feedthrough::kLagged, 1e-3, 0.9999999},
                         Known{"rs-xx-jacobi", Feedthrough::kLagged, 5e-4, 0.99999985}}) {
    const verdict::MapSpectrum m =
        run::macro_step_spectrum(scene, parse_case(k.name), options_of(scene, k.feedthrough, k.H));
    ASSERT_TRUE(m.computed) << label(k) << ": " << m.why_not;
    EXPECT_LT(m.rho, 1.0) << label(k);
    EXPECT_NEAR(m.rho, k.rho, 1e-7) << label(k);
    EXPECT_EQ(m.micro_steps, 1) << label(k);
  }
}

// rs-xt-gauss-seidel at 5e-4 s diverges at t = 0.43 s when the run goes on:
// labelled unstable, and its own defect triples over the last eighth of
// the 0.25 s run; a stable coupling's does not grow.
TEST(MovingRunDefect, FlagsTheRunThatDivergesLater) {
  const Scene scene = test::paper_scene();
  const RunRecord r =
      executed(scene, "rs-xt-gauss-seidel", Feedthrough::kLagged, 5e-4, "inproc", nullptr, nullptr);
  EXPECT_EQ(r.status, "amplified") << r.message;
  EXPECT_TRUE(r.defect_grows) << "defect growth " << r.defect_growth.value_or(0);
  EXPECT_NE(r.message.find("defect grew"), std::string::npos) << r.message;

  const RunRecord ok =
      executed(scene, "rs-xt-gauss-seidel", Feedthrough::kLagged, 1e-4, "inproc", nullptr, nullptr);
  EXPECT_EQ(ok.status, "ok") << ok.message;
  EXPECT_FALSE(ok.defect_grows) << "defect growth " << ok.defect_growth.value_or(0);
  EXPECT_LT(*ok.defect_growth, verdict::kDefectGrowth);
}

// The defect's growth: the last eighth against the eighths before it from
// the second quarter on; an exponential gives its rate back.
TEST(MovingRunDefect, AnExponentialGivesItsRate) {
  const double dt = 1e-3, rate = 30;
  std::vector<double> d(801);
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = 1e-3 * std::exp(rate * dt * double(i));
  const verdict::DefectGrowth g = verdict::defect_growth(d, dt);
  EXPECT_TRUE(g.grows);
  EXPECT_NEAR(g.rate_per_s, rate, 0.01 * rate);
  std::vector<double> flat(801);
  for (std::size_t i = 0; i < flat.size(); ++i) flat[i] = 1e-3 * (1.5 + std::sin(0.3 * double(i)));
  EXPECT_FALSE(verdict::defect_growth(flat, dt).grows);
}

}  // namespace
}  // namespace railcosim
