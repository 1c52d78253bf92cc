#include <gtest/gtest.h>

#include <cmath>

#include "hertz.hpp"
#include "test_support.hpp"
#include "track_model.hpp"

namespace railcosim {
namespace {

// Winkler beam on an elastic foundation: a point load P on an infinite beam
// deflects it by P beta / (2 k) under the load, beta = (k / (4 EI))^(1/4). The
// discrete supports are smeared into k = (pad and ballast in series) / l.
double winkler_deflection(const Scene& s) {
  const double support =
      s.pad_stiffness * s.ballast_stiffness / (s.pad_stiffness + s.ballast_stiffness);
  const double k = support / s.sleeper_spacing;
  const double beta = std::pow(k / (4.0 * s.young_modulus * s.second_moment), 0.25);
  return s.load() * beta / (2.0 * k);
}

Scene scene_with_load_at(double x) {
  Scene s = test::paper_scene();
  s.initial_position = x;
  s.end_time = s.macro_step;  // statics only: the load need not travel
  s.validate();
  return s;
}

double deflection_under_load(const Scene& s) {
  const StaticState st = solve_statics(s);
  return rail_displacement_at(contact_path(s), 0.0, st.rail_w, st.rail_theta);
}

TEST(Statics, WinklerClosedFormUnderASleeper) {
  const Scene s = scene_with_load_at(15.3);  // over sleeper 25, mid-track
  const double expected = winkler_deflection(s);
  EXPECT_NEAR(expected, 1.81e-3, 0.01e-3);  // the figure the model table implies
  // Discrete supports and a finite track: within 3% of the smeared closed form.
  EXPECT_NEAR(deflection_under_load(s), expected, 0.03 * expected);
}

TEST(Statics, LoadAtMidSpanDeflectsMoreThanOverASleeper) {
  EXPECT_GT(deflection_under_load(scene_with_load_at(15.0)),
            deflection_under_load(scene_with_load_at(15.3)));
}

TEST(Statics, BallastCarriesTheWholeLoad) {
  const Scene s = test::paper_scene();
  const StaticState st = solve_statics(s);
  double sum = 0;
  for (double z : st.sleeper) sum += s.ballast_stiffness * z;
  EXPECT_NEAR(sum, s.load(), 1e-9 * s.load());
}

TEST(Statics, HertzForceEqualsTheLoad) {
  const Scene s = test::paper_scene();
  const StaticState st = solve_statics(s);
  const double w_c = rail_displacement_at(contact_path(s), 0.0, st.rail_w, st.rail_theta);
  EXPECT_NEAR(hertz_force(s.hertz_constant, st.wheel - w_c), s.load(), 1e-9 * s.load());
  EXPECT_NEAR(st.contact_force, s.load(), 1e-12 * s.load());
}

TEST(Hertz, PenetrationSolveSatisfiesItsEquation) {
  const double K = 92.86e9;
  for (double c : {0.0, 1e-12, 1e-9, 1e-6}) {
    for (double d0 : {-1e-4, 1e-6, 1e-4, 1e-3}) {
      const double delta = hertz_solve_penetration(K, d0, c);
      EXPECT_NEAR(delta + c * hertz_force(K, delta), d0, 1e-14 + 1e-12 * std::abs(d0))
          << "c = " << c << ", d0 = " << d0;
    }
  }
}

}  // namespace
}  // namespace railcosim
