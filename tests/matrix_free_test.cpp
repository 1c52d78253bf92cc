// The matrix-free growth rate (run/matrix_free.hpp), measured through the
// participants on node processes over TCP (their own save and restore),
// against the dense spectral radius of the same macro-step map built in
// process (run/spectral.hpp): one unstable case of the paper scene, one
// stable.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "remote/transport.hpp"
#include "run/matrix_free.hpp"
#include "run/spectral.hpp"
#include "run/stability.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace matrix_free_test {

struct Compared {
  run::MapSpectrum dense;
  run::MatrixFreeRho free;
};

Compared compare(const char* name, double H, long max_steps) {
  const Scene scene = test::paper_scene();
  run::RunOptions o;
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  const CaseSpec spec = parse_case(name);
  Compared c;
  c.dense = run::macro_step_spectrum(scene, spec, o);
  // The micro steps of the dense map's step at rest, fixed for the nodes too.
  const Scene fixed =
      with_keys(scene, {{"simulation.micro_steps", std::int64_t{c.dense.micro_steps}}});
  remote::NodePool pool;
  remote::TransportSetup setup;
  setup.pool = &pool;
  c.free = run::matrix_free_rho(fixed, spec, o, remote::kTcpTransport, setup, max_steps);
  return c;
}

// rs-xx-jacobi at H = 1e-3 s: rho = 1.055 by the dense map (54 /s); over
// TCP the perturbation grows 1e6 times within the steps allowed, at the
// dense rate to 2 %.
TEST(MatrixFree, AnUnstableCouplingOverTcpGrowsAtTheDenseRate) {
  const Compared c = compare("rs-xx-jacobi", 1e-3, 1000);
  ASSERT_TRUE(c.dense.computed) << c.dense.why_not;
  EXPECT_NEAR(c.dense.rho, 1.055, 0.001);
  EXPECT_GE(c.free.growth, run::kMatrixFreeGrowth);
  EXPECT_LT(c.free.steps, 1000);
  EXPECT_NEAR(c.free.rate_per_s, c.dense.rate_per_s, 0.02 * c.dense.rate_per_s)
      << "matrix-free rho " << c.free.rho << " after " << c.free.steps << " steps, dense "
      << c.dense.rho;
}

// rs-xx-gauss-seidel at H = 1e-4 s is stable (dense rho = 0.9999993, a
// lightly damped mode): the perturbation does not grow over 2000 steps, and
// the matrix-free rho is the dense one to 1e-3.
TEST(MatrixFree, AStableCouplingOverTcpDoesNotGrow) {
  const long steps = 2000;
  const Compared c = compare("rs-xx-gauss-seidel", 1e-4, steps);
  ASSERT_TRUE(c.dense.computed) << c.dense.why_not;
  EXPECT_LE(c.dense.rho, 1.0);
  EXPECT_EQ(c.free.steps, steps);
  EXPECT_LT(c.free.growth, 10.0);
  EXPECT_NEAR(c.free.rho, c.dense.rho, 1e-3)
      << "matrix-free rho " << c.free.rho << ", dense " << c.dense.rho;
}

// An implicit run of the paper scene, in process, judged as master run
// judges it (the probe, then the matrix-free rho: implicit coupling has no
// dense map).
run::RunRecord implicit_run(const char* name, double H, engine::InputMode inputs) {
  const Scene scene = test::paper_scene();
  run::RunOptions o;
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  o.coupling.method = engine::CouplingMethod::kImplicit;
  o.coupling.inputs = inputs;
  o.coupling.accelerator.kind = engine::AcceleratorKind::kIqnIls;
  const CaseSpec spec = parse_case(name);
  run::RunRecord r =
      run::run_cosim(scene, spec, o, remote::inproc_factory(scene), remote::kInprocTransport);
  run::assess_growth(r, scene, spec, o);
  return r;
}

// Converged implicit coupling with linear inputs (the ramp over a step starts
// at the coupling data at t_n, which the perturbation moves) carries rho and
// its rate. At H = 1e-4 s on wr-xx-jacobi its slowest mode is the rail's
// nearly undamped one, which the trapezoidal rule keeps at |lambda| = 1 and
// the explicit coupling's dense map puts at rho = 0.9999993: the matrix-free
// rho is that one to the measure's trust near 1 (a few times 1 / the steps
// taken); at H = 1e-3 s on rs-xx-jacobi, where the explicit coupling grows
// (rho = 1.055), the converged coupling is stable.
TEST(MatrixFree, ImplicitLinearRunsCarryRhoAndItsRate) {
  const run::RunRecord r = implicit_run("wr-xx-jacobi", 1e-4, engine::InputMode::kLinear);
  ASSERT_TRUE(r.matrix_free_rho.has_value()) << r.spectral_note;
  const double trust = 3.0 / static_cast<double>(*r.matrix_free_steps);
  EXPECT_EQ(*r.matrix_free_steps, run::kMatrixFreeMaxSteps);
  EXPECT_NEAR(*r.matrix_free_rho, 0.9999993, trust);
  EXPECT_LE(*r.matrix_free_rho, 1.0 + trust);
  // rho = exp(slope) and the rate = slope / H: ln(rho) / H to round-off.
  EXPECT_NEAR(*r.matrix_free_rate, std::log(*r.matrix_free_rho) / 1e-4, 1e-12);
  EXPECT_EQ(r.stability, "stable");

  const run::RunRecord big = implicit_run("rs-xx-jacobi", 1e-3, engine::InputMode::kLinear);
  ASSERT_TRUE(big.matrix_free_rho.has_value()) << big.spectral_note;
  EXPECT_LE(*big.matrix_free_rho, 1.0 + 1.0 / static_cast<double>(*big.matrix_free_steps));
  EXPECT_EQ(big.stability, "stable");
}

// With held inputs the converged step never reads the coupling data at t_n:
// no rho is claimed, and the note says why.
TEST(MatrixFree, ImplicitHeldInputsSayWhyNoRho) {
  const run::RunRecord r = implicit_run("wr-xx-jacobi", 1e-4, engine::InputMode::kHold);
  EXPECT_FALSE(r.matrix_free_rho.has_value());
  EXPECT_NE(r.spectral_note.find("does not take the coupling data at t_n"), std::string::npos)
      << r.spectral_note;
}

}  // namespace matrix_free_test
}  // namespace railcosim
