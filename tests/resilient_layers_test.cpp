// Under-sleeper pads and under-ballast mats (common/resilient_layers.hpp):
// the transmissibility of a mass on a layer against its closed form, the
// track's insertion loss of each layer per one-third-octave band with its
// resonance against the closed form, and the scene's refusals.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include "newmark.hpp"
#include "resilient_layers.hpp"
#include "scene_text.hpp"
#include "statics.hpp"
#include "test_support.hpp"
#include "track_model.hpp"

namespace railcosim {
namespace {

constexpr double kPi = std::numbers::pi;

// The paper's track with a pad: k'' = 1e8 N/m^3 (0.1 N/mm^3) over 0.1 m^2,
// eta = 0.2, a 50 kg share of ballast under the pad.
std::vector<SceneEdit> pad_keys() {
  return {{"under_sleeper_pads.stiffness", 1e8},
          {"under_sleeper_pads.loss_factor", 0.2},
          {"under_sleeper_pads.area", 0.1},
          {"ballast.mass", 50.0}};
}
// ... or a mat: k'' = 1e7 N/m^3 (0.01 N/mm^3) over one rail's share of a
// bay (0.6 m x 1.75 m), eta = 0.2, 300 kg of ballast on it.
std::vector<SceneEdit> mat_keys() {
  return {{"under_ballast_mats.stiffness", 1e7},
          {"under_ballast_mats.loss_factor", 0.2},
          {"under_ballast_mats.area", 1.05},
          {"ballast.mass", 300.0}};
}

std::vector<SceneEdit> plus(std::vector<SceneEdit> a, const std::vector<SceneEdit>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

ParticipantSpec holding(std::initializer_list<Component> parts) {
  ParticipantSpec p;
  p.role = "test";
  for (Component c : parts) p.parts.add(c);
  return p;
}

// ---- 1. A mass on a layer: T(w) = |k + i w c| / |k + i w c - m w^2| -------

// The closed form of the model's damper (viscous, c = eta k / w_ref).
double viscous_transmissibility(double k, double c, double m, double w) {
  const std::complex<double> z(k, w * c);
  return std::abs(z) / std::abs(z - m * w * w);
}

// One sleeper on its pad over a rigid base (a ballast 1e12 N/m stiff), a
// harmonic force F0 sin(w t) on the sleeper from rest: the steady-state
// amplitude of the force into the ground over F0, from the product's
// assembly and integrator.
double simulated_transmissibility(const Scene& scene, double f) {
  Structure s = assemble(scene, holding({Component::kSleepers}));
  const int dof = s.layout.sleeper[0];
  const double w = 2 * kPi * f, period = 1.0 / f, H = period / 200;
  Newmark nm(s, H, 1e-13);
  nm.set_input_hook([&](double t) { s.load[dof] = std::sin(w * t); });
  nm.set_state(Vector::Zero(s.layout.size), Vector::Zero(s.layout.size), 0.0);
  // 0.3 s of transient (it decays as exp(-eta w0 t / 2), below 1e-8), then
  // ten periods projected on e^{-i w t} (exact for a harmonic on whole periods).
  const long settle = std::lround(0.3 / H) / 200 * 200, measure = 10 * 200;
  std::complex<double> sum = 0;
  for (long n = 0; n < settle + measure; ++n) {
    const double t0 = n * H, t1 = (n + 1) * H;
    nm.advance(t0, t1);
    if (n + 1 > settle) {
      const double g =
          ballast_forces(scene, s.layout, nm.state().u, nm.state().v, nullptr, nullptr)[0];
      sum += g * std::exp(std::complex<double>(0, -w * t1));
    }
  }
  return 2.0 * std::abs(sum) / static_cast<double>(measure);
}

TEST(ResilientLayers, SleeperOnPadTransmissibilityMatchesTheClosedForm) {
  // One sleeper (m_s = 90.84 kg) and no rail: the mass on the pad is m_s.
  const Scene paper = test::paper_scene();
  const double k = 1e8 * 0.1, m = paper.sleeper_mass, eta = 0.2;
  const double f0 = std::sqrt(k / m) / (2 * kPi);
  const Scene scene =
      with_keys(paper, plus(pad_keys(), {{"sleepers.count", std::int64_t{1}},
                                         {"vehicle.initial_position", 0.1},
                                         {"simulation.end_time", 1e-4},
                                         {"ballast.stiffness", 1e12},
                                         {"under_sleeper_pads.reference_frequency", f0}}));
  const SpringDamper pad = layer_spring(*scene.sleeper_pad);
  ASSERT_DOUBLE_EQ(pad.k, k);
  ASSERT_DOUBLE_EQ(pad.c, eta * k / (2 * kPi * f0));
  for (double ratio : {0.5, 1.0, std::sqrt(2.0), 2.0, 4.0}) {
    const double f = ratio * f0, w = 2 * kPi * f;
    const double expected = viscous_transmissibility(pad.k, pad.c, m, w);
    const double got = simulated_transmissibility(scene, f);
    std::printf("f / f0 = %.3f: T = %.5f, closed form %.5f\n", ratio, got, expected);
    EXPECT_NEAR(got / expected, 1.0, 5e-3)
        << "f / f0 = " << ratio << ": T = " << got << " against the closed form " << expected;
  }
  // At w_ref = w0 the viscous damper is the hysteretic loss factor exactly:
  // T(w0) = |1 + i eta| / eta.
  EXPECT_NEAR(simulated_transmissibility(scene, f0) / (std::sqrt(1 + eta * eta) / eta), 1.0, 5e-3);
}

// ---- 2. The track's insertion loss of each layer ---------------------------

// The force into the ground (summed over the sleepers) per unit harmonic
// force on the rail over the middle sleeper, from the assembled M, C, K of
// the track (rail, pads, sleepers, layers, fixed ground).
struct TrackResponse {
  Eigen::MatrixXcd m, c, k;
  int force_dof = 0;
  std::vector<int> base;
  std::vector<double> base_k, base_c;

  explicit TrackResponse(const Scene& scene) {
    const Structure s = assemble(scene, holding({Component::kRail, Component::kSleepers}));
    m = s.M.to_dense().cast<std::complex<double>>();
    c = s.C.to_dense().cast<std::complex<double>>();
    k = s.K.to_dense().cast<std::complex<double>>();
    force_dof =
        s.layout.rail_w[static_cast<std::size_t>(s.layout.pad_node(scene.sleeper_count / 2))];
    base = s.layout.track_base();
    const SpringDamper e = layer_element(scene, find_cut("ss"));
    base_k.assign(base.size(), e.k);
    base_c.assign(base.size(), e.c);
  }
  double ground_force(double f) const {
    const double w = 2 * kPi * f;
    const std::complex<double> iw(0, w);
    const Eigen::MatrixXcd a = k + iw * c - w * w * m;
    Eigen::VectorXcd b = Eigen::VectorXcd::Zero(a.rows());
    b[force_dof] = 1.0;
    const Eigen::VectorXcd u = a.partialPivLu().solve(b);
    std::complex<double> sum = 0;
    for (std::size_t i = 0; i < base.size(); ++i) sum += (base_k[i] + iw * base_c[i]) * u[base[i]];
    return std::abs(sum);
  }
};

// Band n (centre 10^(n/10) Hz): 10 log10 of the band's energy, the mean of
// |H|^2 over 24 points spread evenly in log frequency across the band.
double band_level(const TrackResponse& r, int n) {
  const double lo = std::pow(10.0, (n - 0.5) / 10), hi = std::pow(10.0, (n + 0.5) / 10);
  double e = 0;
  for (int j = 0; j < 24; ++j) {
    const double f = lo * std::pow(hi / lo, (j + 0.5) / 24);
    e += std::pow(r.ground_force(f), 2) * f;  // |H|^2 df with df proportional to f
  }
  return 10 * std::log10(e);
}

// The frequency of the largest |H| between a and b Hz (a scan at 0.5 %).
double peak_frequency(const TrackResponse& r, double a, double b) {
  double best = a, top = 0;
  for (double f = a; f <= b; f *= 1.005)
    if (const double h = r.ground_force(f); h > top) {
      top = h;
      best = f;
    }
  return best;
}

// 20 sleepers (the rail's bending waves have decayed well before its ends).
Scene short_track(const std::vector<SceneEdit>& keys) {
  return with_keys(test::paper_scene(), plus(keys, {{"sleepers.count", std::int64_t{20}},
                                                    {"vehicle.initial_position", 1.0},
                                                    {"simulation.end_time", 0.01}}));
}

void check_insertion_loss(const Scene& plain, const Scene& layered, double closed_form,
                          const char* name) {
  const TrackResponse ref(plain), with(layered);
  const double f_peak = peak_frequency(with, 5.0, 200.0);
  std::printf("%s: resonance %.2f Hz, closed form %.2f Hz (%+.1f %%)\n", name, f_peak, closed_form,
              100 * (f_peak / closed_form - 1));
  EXPECT_NEAR(f_peak / closed_form, 1.0, 0.10)
      << name << ": the track's resonance " << f_peak << " Hz against the closed form "
      << closed_form << " Hz";
  const int peak_band = static_cast<int>(std::lround(10 * std::log10(f_peak)));
  for (int n = 0; n <= 23; ++n) {
    const double il = band_level(ref, n) - band_level(with, n);
    std::printf("%s band %5.1f Hz: IL %+6.2f dB\n", name, std::pow(10.0, n / 10.0), il);
    if (n == peak_band) {
      EXPECT_LT(il, -3.0) << name << ": no amplification at the resonance";
    }
    if (std::pow(10.0, (n - 0.5) / 10) >= 2.0 * closed_form) {
      EXPECT_GT(il, 3.0) << name << ": no loss in the band of " << std::pow(10.0, n / 10.0)
                         << " Hz, above the resonance";
    }
  }
}

TEST(ResilientLayers, PadInsertionLossAmplifiesAtTheNewResonanceAndIsolatesAbove) {
  const Scene plain = short_track({}), pad = short_track(pad_keys());
  // The sleeper and the rail over one bay on the pad in series with the
  // ballast under it.
  const double k = 1.0 / (1.0 / pad.sleeper_pad->stiffness() + 1.0 / pad.ballast_stiffness);
  const double closed = std::sqrt(k / mass_above_pad(pad)) / (2 * kPi);
  ASSERT_DOUBLE_EQ(mass_above_pad(pad), 90.84 + 7850 * 63.8e-4 * 0.6);
  check_insertion_loss(plain, pad, closed, "pad");
}

TEST(ResilientLayers, MatInsertionLossAmplifiesAtTheNewResonanceAndIsolatesAbove) {
  const Scene plain = short_track({}), mat = short_track(mat_keys());
  // The sleeper, the rail over one bay and the ballast on the mat.
  const double closed = std::sqrt(mat.ballast_mat->stiffness() / mass_above_mat(mat)) / (2 * kPi);
  ASSERT_DOUBLE_EQ(mass_above_mat(mat), 90.84 + 7850 * 63.8e-4 * 0.6 + 300);
  check_insertion_loss(plain, mat, closed, "mat");
}

// ---- 3. The scene's refusals ----------------------------------------------

std::string refusal(const std::vector<SceneEdit>& keys) {
  try {
    with_keys(test::paper_scene(), keys);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ResilientLayers, TheSceneRefusesALayerWithoutItsBallastMassAndAMassWithoutALayer) {
  std::vector<SceneEdit> no_mass = pad_keys();
  no_mass.pop_back();
  EXPECT_NE(refusal(no_mass).find("key 'ballast.mass': missing: a resilient layer needs the "
                                  "ballast's mass under one sleeper"),
            std::string::npos)
      << refusal(no_mass);
  EXPECT_NE(refusal({{"ballast.mass", 300.0}})
                .find("key 'ballast.mass': applies only with [under_sleeper_pads] or "
                      "[under_ballast_mats]"),
            std::string::npos);
  std::vector<SceneEdit> no_area = mat_keys();
  no_area.erase(no_area.begin() + 2);
  EXPECT_NE(refusal(no_area).find("key 'under_ballast_mats.area': missing"), std::string::npos)
      << refusal(no_area);
  EXPECT_NE(refusal(plus(pad_keys(), {{"under_sleeper_pads.loss_factor", -0.1}}))
                .find("key 'under_sleeper_pads.loss_factor': must lie between 0 and 2"),
            std::string::npos);
}

}  // namespace
}  // namespace railcosim
