// The stability of multirate runs (run/spectral.hpp over a slow window):
// the map of a multirate plan spans its slow window, so its rate per second
// is that of the coupled dynamics, not of the window: the wheel/rail
// instability of wr-xt+ss-xx-jacobi on the soil scene keeps its rate when
// the soil's cut exchanges 10 or 50 times less often (rho = rho_H^M), the
// parked multirate run grows, and a stable multirate plan stays inside the
// unit circle.
#include <gtest/gtest.h>

#include <cmath>

#include "run/assess.hpp"
#include "run/runner.hpp"
#include "run/spectral.hpp"
#include "test_support.hpp"

namespace railcosim::multirate_stability_test {
namespace {

run::RunOptions soil_options(const Scene& scene, long ss_window) {
  run::RunOptions o;
  o.macro_step = 1e-4;
  o.tolerance = scene.tolerance;
  if (ss_window > 1) o.cut_windows = {{"ss", ss_window}, {"wr", 1}};
  return o;
}

Scene soil_scene() {
  return load_scene(test::source_path("scenes/soil.toml"));
}

TEST(MultirateMap, TheFastCutsInstabilityKeepsItsRateAtAnySlowWindow) {
  const Scene scene = soil_scene();
  const CaseSpec spec = parse_case("wr-xt+ss-xx-jacobi");
  const verdict::MapSpectrum one = run::macro_step_spectrum(scene, spec, soil_options(scene, 1));
  ASSERT_TRUE(one.computed) << one.why_not;
  ASSERT_GT(one.rho, 1.01);
  for (long M : {10L, 50L}) {
    const verdict::MapSpectrum multi =
        run::macro_step_spectrum(scene, spec, soil_options(scene, M));
    ASSERT_TRUE(multi.computed) << multi.why_not;
    EXPECT_NEAR(multi.rate_per_s, one.rate_per_s, 0.01 * one.rate_per_s) << "M = " << M;
    EXPECT_NEAR(std::log(multi.rho), static_cast<double>(M) * std::log(one.rho),
                0.01 * static_cast<double>(M) * std::log(one.rho))
        << "M = " << M;
  }
  // The parked multirate run grows too (so fast that the contact's
  // non-linearity bounds it within the probe: its rate is no measure).
  EXPECT_TRUE(run::probe_stability(scene, spec, soil_options(scene, 10)).unstable);
}

TEST(MultirateMap, AStableMultiratePlanStaysInsideTheUnitCircle) {
  const Scene scene = soil_scene();
  const verdict::MapSpectrum m =
      run::macro_step_spectrum(scene, parse_case("wr-xx+ss-xt-jacobi"), soil_options(scene, 10));
  ASSERT_TRUE(m.computed) << m.why_not;
  EXPECT_LT(m.rho, 1.0);
  EXPECT_LT(m.rate_per_s, 0.0);
}

}  // namespace
}  // namespace railcosim::multirate_stability_test
