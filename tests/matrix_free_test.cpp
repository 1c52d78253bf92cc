// The matrix-free growth rate (run/matrix_free.hpp), measured through the
// participants on node processes over TCP (their own save and restore),
// against the dense spectral radius of the same macro-step map built in
// process (run/spectral.hpp): one unstable case of the paper scene, one
// stable, one implicit; and the dense map of implicit runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "remote/transport.hpp"
#include "run/assess.hpp"
#include "run/matrix_free.hpp"
#include "run/spectral.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace matrix_free_test {

struct Compared {
  verdict::MapSpectrum dense;
  verdict::MatrixFreeRho free;
};

Compared compare(const char* name, double H, long max_steps, run::RunOptions o = {}) {
  const Scene scene = test::paper_scene();
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
  EXPECT_GE(c.free.growth, verdict::kMatrixFreeGrowth);
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

// Implicit coupling with IQN-ILS and these inputs.
run::RunOptions implicit_options(engine::InputMode inputs) {
  run::RunOptions o;
  o.coupling.method = engine::CouplingMethod::kImplicit;
  o.coupling.inputs = inputs;
  o.coupling.accelerator.kind = engine::AcceleratorKind::kIqnIls;
  return o;
}

// Converged implicit coupling with held inputs never reads the coupling data
// at t_n: the measure's first step takes one pass from them, which moves the
// participants' inner states. rs-xt-gauss-seidel at H = 5e-4 s so coupled
// grows (the dense map of the converged step: rho = 1.0197, 38.9 /s); over
// TCP the perturbation carried into the nodes grows at that rate to 5 %.
TEST(MatrixFree, ImplicitHeldInputsOverTcpGrowAtTheDenseRate) {
  const Compared c =
      compare("rs-xt-gauss-seidel", 5e-4, 1000, implicit_options(engine::InputMode::kHold));
  ASSERT_TRUE(c.dense.computed) << c.dense.why_not;
  EXPECT_NEAR(c.dense.rho, 1.0197, 0.0005);
  EXPECT_GT(c.free.carried, verdict::kMatrixFreeCarried);
  EXPECT_GE(c.free.growth, verdict::kMatrixFreeImplicitGrowth);
  EXPECT_NEAR(c.free.rate_per_s, c.dense.rate_per_s, 0.05 * c.dense.rate_per_s)
      << "matrix-free rho " << c.free.rho << " after " << c.free.steps << " steps, dense "
      << c.dense.rho;
}

// An implicit run of the paper scene, in process, judged as master run
// judges it: the dense map of its converged step.
run::RunRecord implicit_run(const char* name, double H, engine::InputMode inputs) {
  const Scene scene = test::paper_scene();
  run::RunOptions o = implicit_options(inputs);
  o.macro_step = H;
  o.tolerance = scene.tolerance;
  const CaseSpec spec = parse_case(name);
  run::RunRecord r =
      run::run_cosim(scene, spec, o, remote::inproc_factory(scene), remote::kInprocTransport);
  run::assess_growth(r, scene, spec, o);
  return r;
}

// Every implicit run in process carries the map's rho and its rate, whatever
// its inputs. At H = 1e-4 s on wr-xx-jacobi the slowest mode with ramped
// inputs or waveforms is the rail's lightly damped one (the explicit
// coupling's map: rho = 0.9999993), and held inputs grow; at H = 1e-3 s on rs-xx-jacobi, where the
// explicit coupling grows (rho = 1.055), substep waveforms make the converged coupling stable, and
// held inputs make it grow faster still (rho = 8.44: the run diverges).
TEST(MatrixFree, ImplicitRunsCarryTheMapsRhoAndItsRate) {
  for (engine::InputMode inputs :
       {engine::InputMode::kHold, engine::InputMode::kLinear, engine::InputMode::kWaveform3}) {
    const run::RunRecord r = implicit_run("wr-xx-jacobi", 1e-4, inputs);
    ASSERT_TRUE(r.spectral_radius.has_value()) << r.spectral_note;
    EXPECT_EQ(r.stability_basis, "map");
    EXPECT_NEAR(*r.spectral_rate, std::log(*r.spectral_radius) / 1e-4, 1e-9);
    if (inputs == engine::InputMode::kHold) {
      // Held inputs grow slowly here (rho = 1.00036, 3.6 /s; master run calls
      // the run amplified).
      EXPECT_NEAR(*r.spectral_radius, 1.00036, 1e-5);
      EXPECT_EQ(r.stability, "unstable");
    } else {
      EXPECT_NEAR(*r.spectral_radius, 0.9999993, 1e-6);
      EXPECT_EQ(r.stability, "stable");
    }
  }
  const run::RunRecord wave = implicit_run("rs-xx-jacobi", 1e-3, engine::InputMode::kWaveform3);
  ASSERT_TRUE(wave.spectral_radius.has_value()) << wave.spectral_note;
  EXPECT_LE(*wave.spectral_radius, 1.0);
  EXPECT_EQ(wave.stability, "stable");
  const run::RunRecord held = implicit_run("rs-xx-jacobi", 1e-3, engine::InputMode::kHold);
  ASSERT_TRUE(held.spectral_radius.has_value()) << held.spectral_note;
  EXPECT_NEAR(*held.spectral_radius, 8.44, 0.01);
  EXPECT_EQ(held.stability, "unstable");
}

}  // namespace matrix_free_test
}  // namespace railcosim
