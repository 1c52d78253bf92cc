#include <gtest/gtest.h>

#include <cmath>

#include "hertz.hpp"
#include "statics.hpp"
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

// The static state of the whole model, solved as one system.
struct Global {
  Structure s;
  Vector u;
  std::vector<double> at(const std::vector<int>& dofs) const {
    std::vector<double> v;
    for (int d : dofs) v.push_back(u[d]);
    return v;
  }
  double rail_under_load(const Scene& scene) const {
    return rail_displacement_at(contact_path(scene), 0.0, at(s.layout.rail_w),
                                at(s.layout.rail_theta));
  }
};

Global global_statics(const Scene& scene) {
  ParticipantSpec whole;
  whole.role = "monolithic";
  whole.parts = Parts::all(scene);
  Global g{assemble(scene, whole), {}};
  g.u = solve_static(g.s, Vector::Zero(g.s.layout.size));
  return g;
}

double deflection_under_load(const Scene& s) {
  return global_statics(s).rail_under_load(s);
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
  const Global g = global_statics(s);
  double sum = 0;
  for (double z : g.at(g.s.layout.sleeper)) sum += s.ballast_stiffness * z;
  EXPECT_NEAR(sum, s.load(), 1e-9 * s.load());
}

TEST(Statics, HertzForceEqualsTheLoad) {
  const Scene s = test::paper_scene();
  const Global g = global_statics(s);
  const double w_c = g.rail_under_load(s);
  // Newton leaves rounding only: the contact carries the load to ~1e-14.
  EXPECT_NEAR(hertz_force(s.hertz_constant, g.u[g.s.layout.wheel] - w_c), s.load(),
              1e-12 * s.load());
}

// With a lumped soil the load path runs wheel -> rail -> pads -> sleepers ->
// ballast -> soil masses -> soil springs -> ground: every layer carries m g.
TEST(Statics, LumpedSoilCarriesTheWholeLoad) {
  const Scene s = load_scene(test::source_path("scenes/soil.toml"));
  const Global g = global_statics(s);
  const auto z = g.at(g.s.layout.sleeper), f = g.at(g.s.layout.soil);
  ASSERT_EQ(z.size(), f.size());
  double ballast = 0, ground = 0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    ballast += s.ballast_stiffness * (z[i] - f[i]);
    ground += s.soil_stiffness * f[i];
  }
  EXPECT_NEAR(ballast, s.load(), 1e-9 * s.load());
  EXPECT_NEAR(ground, s.load(), 1e-9 * s.load());
  // The soil yields: the rail deflects more than on the fixed ground.
  EXPECT_GT(g.rail_under_load(s), deflection_under_load(test::paper_scene()));
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
