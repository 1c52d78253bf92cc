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

}  // namespace matrix_free_test
}  // namespace railcosim
