// Multirate coupling (engine/rate_plan, fast_group, multirate): the rates
// a case's windows give, the order of accuracy each waveform degree keeps
// across the rates on masses coupled by springs against their closed form,
// and implicit steps that re-run the fast windows from checkpoints.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "engine/multirate.hpp"
#include "test_support.hpp"

namespace railcosim::multirate_test {
namespace {

using engine::RatePlan;
using engine::Routing;

// A chain a - b - c: participant p's interfaces to its neighbours, in order.
Routing chain(std::size_t n) {
  Routing r(n);
  for (std::size_t p = 0; p < n; ++p) {
    if (p > 0) r[p].push_back({static_cast<int>(p - 1), p - 1 > 0 ? 1 : 0});
    if (p + 1 < n) r[p].push_back({static_cast<int>(p + 1), 0});
  }
  return r;
}

const std::vector<std::string> kRoles = {"vehicle", "track", "soil", "deep"};

TEST(RatePlan, OneSlowNeighbourIsViewedInsideTheFastGroup) {
  const RatePlan r = engine::plan_rates(chain(3), {{1}, {1, 10}, {10}}, kRoles);
  ASSERT_TRUE(r.multirate());
  EXPECT_EQ(r.ratio, 10);
  EXPECT_EQ(r.window, (std::vector<long>{1, 1, 10}));
  EXPECT_EQ(r.fast, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(r.slow, (std::vector<std::size_t>{2}));
  EXPECT_EQ(r.describe(kRoles),
            "at H: vehicle track\nat 10 H: soil\nviews inside the group: soil (interfaces 0)\n"
            "the group's interfaces: track.1\n");
  // Inner: vehicle <-> track, track.1 <-> view of soil (inner participant 2).
  EXPECT_EQ(r.inner[1][1].participant, 2);
  EXPECT_EQ(r.inner[2][0].participant, 1);
  EXPECT_EQ(r.inner[2][0].interface, 1);
  // Outer: the group (0) <-> soil (1).
  EXPECT_EQ(r.outer_members, (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(r.outer[0][0].participant, 1);
  EXPECT_EQ(r.outer[1][0].participant, 0);
}

TEST(RatePlan, TwoSlowParticipantsCoupleAtTheSlowWindow) {
  const RatePlan r = engine::plan_rates(chain(4), {{1}, {1, 4}, {4, 4}, {4}}, kRoles);
  EXPECT_EQ(r.slow, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(r.viewed, (std::vector<std::size_t>{2}));
  // soil <-> deep at the outer level, soil's first interface to the group.
  EXPECT_EQ(r.outer[1][0].participant, 0);
  EXPECT_EQ(r.outer[1][1].participant, 2);
  EXPECT_EQ(r.outer[2][0].participant, 1);
}

TEST(RatePlan, WindowsThatCannotBeCoupledAreRefusedByName) {
  EXPECT_FALSE(engine::plan_rates(chain(3), {{1}, {1, 1}, {1}}, kRoles).multirate());
  auto refused = [](const std::vector<std::vector<long>>& w, const std::string& words) {
    try {
      engine::plan_rates(chain(4), w, kRoles);
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused({{1}, {1, 4}, {4, 8}, {8}}, "cuts at 4 and 8 finest windows");
  refused({{1}, {1, 4}, {4, 1}, {1}}, "a cut between track and soil at 4 finest windows");
  refused({{4}, {4, 4}, {4, 4}, {4}}, "nothing steps at H");
}

// Masses on springs to the ground in a chain, each coupled to its
// neighbours by springs; each participant holds one mass, sends its
// displacement and integrates with RK4 at `substeps` per window against its
// neighbours' displacements as waveforms. It counts where it is restored.
class Mass final : public Participant {
 public:
  Mass(double m, double k, std::vector<double> kc, double x0, double window)
      : m_(m), k_(k), kc_(std::move(kc)), x_(x0), H_(window) {}
  std::string name() const override { return "mass"; }
  Channels channels() const override { return {}; }
  CouplingData statics(const CouplingData&) override { return out(); }
  StepResult initialize(const CouplingData&) override { return result(); }
  void set_inputs(long n, const CouplingData& in) override {
    InputWaveforms w;
    for (const InterfaceData& d : in) {
      w.emplace_back(0, 1);
      w.back().add(static_cast<double>(n) * H_, d.displacement);
    }
    in_ = w;
  }
  void set_input_waveforms(long, const InputWaveforms& w) override { in_ = w; }
  void record_samples(bool) override {}
  OutputSamples step_samples() const override { return samples_; }
  CouplingData outputs() override { return out(); }
  void start_step(long n) override {
    if (!steps.empty() && n <= steps.back()) restarts.emplace_back(steps.back(), n);
    steps.push_back(n);
    n_ = n;
  }
  StepResult finish_step() override;
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {{x_, v_}}; }
  void restore(const ParticipantState& s) override { x_ = s.values[0], v_ = s.values[1]; }

  double x() const { return x_; }
  std::vector<long> steps;                      // the windows started
  std::vector<std::pair<long, long>> restarts;  // (last window, window started again)
  static constexpr int kSubsteps = 4;

 private:
  CouplingData out() const { return CouplingData(kc_.size(), InterfaceData{{x_}, {}, {}}); }
  StepResult result() const {
    StepResult r;
    r.outputs = out();
    r.max_abs_displacement = std::abs(x_);
    return r;
  }
  double acc(double t, double x) const {
    double f = -k_ * x;
    for (std::size_t j = 0; j < kc_.size(); ++j) f -= kc_[j] * (x - in_[j].at(t)[0]);
    return f / m_;
  }

  double m_, k_;
  std::vector<double> kc_;
  double x_, v_ = 0, H_;
  long n_ = 0;
  InputWaveforms in_;
  OutputSamples samples_;
};

StepResult Mass::finish_step() {
  const double t0 = static_cast<double>(n_) * H_, h = H_ / kSubsteps;
  samples_.assign(1, OutputSample{.t = t0, .outputs = out()});
  for (int s = 0; s < kSubsteps; ++s) {
    const double t = t0 + s * h;
    test::rk4_step(x_, v_, t, h, [this](double ta, double xa) { return acc(ta, xa); });
    samples_.push_back(
        OutputSample{.t = s + 1 == kSubsteps ? t0 + H_ : t0 + (s + 1) * h, .outputs = out()});
  }
  return result();
}

// Two stiff masses (about 4 and 6 Hz) at the fine window h, and a soft one
// (about 0.5 Hz) at M h: x(t) from the chain's modes.
struct Chain {
  double m[3] = {1.0, 2.0, 4.0}, k[3] = {600.0, 900.0, 30.0}, kc[2] = {300.0, 20.0};

  double x_exact(std::size_t i, double t) const {
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero(), Mm = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 3; ++a) K(a, a) = k[a], Mm(a, a) = m[a];
    for (int c = 0; c < 2; ++c) {
      K(c, c) += kc[c], K(c + 1, c + 1) += kc[c];
      K(c, c + 1) -= kc[c], K(c + 1, c) -= kc[c];
    }
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> e(K, Mm);
    Eigen::Vector3d q = e.eigenvectors().transpose() * Mm * Eigen::Vector3d(0.0, 0.0, 1.0);
    for (int a = 0; a < 3; ++a) q[a] *= std::cos(std::sqrt(e.eigenvalues()[a]) * t);
    return (e.eigenvectors() * q)[static_cast<Eigen::Index>(i)];
  }
};

struct Outcome {
  double error = 0;          // the largest |x3 - exact| at the slow windows' ends
  std::vector<double> x;     // the masses at T
  std::vector<double> slow;  // the slow mass at every fine window's end
  std::vector<std::pair<long, long>> fast_restarts;
  long outer_iterations = 0;
};

// The soft mass starts displaced; implicit coupling with substep waveforms
// of `degree`, iterated to round-off at both levels.
Outcome run_chain(int degree, long M, double h, double T) {
  const Chain c;
  const double Hs = h * static_cast<double>(M);
  Mass a(c.m[0], c.k[0], {c.kc[0]}, 0.0, h), b(c.m[1], c.k[1], {c.kc[0], c.kc[1]}, 0.0, h),
      s(c.m[2], c.k[2], {c.kc[1]}, 1.0, Hs);
  const Routing routing = chain(3);
  engine::CouplingOptions o;
  o.method = engine::CouplingMethod::kImplicit;
  o.inputs =
      static_cast<engine::InputMode>(static_cast<int>(engine::InputMode::kWaveform0) + degree);
  o.convergence = 1e-13;
  o.max_iterations = 60;
  const std::vector<CouplingData> start = {
      {{{0.0}, {}, {}}}, {{{0.0}, {}, {}}, {{1.0}, {}, {}}}, {{{0.0}, {}, {}}}};
  const std::vector<std::string> roles = {"a", "b", "s"};
  std::unique_ptr<engine::MacroSteps> ex;
  const engine::ConvergenceLog* log = nullptr;
  if (M == 1) {  // one rate: the reference of the multirate runs
    auto one = std::make_unique<engine::StepExecutor>(
        std::vector<Participant*>{&a, &b, &s}, routing,
        engine::PlanOptions{Scheme::kGaussSeidel, Feedthrough::kLagged, true}, o, roles, h);
    one->initialize(start);
    log = &one->log();
    ex = std::move(one);
  } else {
    auto multi = std::make_unique<engine::MultirateExecutor>(
        engine::plan_rates(routing, {{1}, {1, M}, {M}}, roles),
        std::vector<Participant*>{&a, &b, &s}, start, Scheme::kGaussSeidel, o, roles, h);
    multi->initialize(start);
    log = &multi->log();
    ex = std::move(multi);
  }
  const long N = std::lround(T / h);
  Outcome out;
  for (long n = 0; n < N; ++n) {
    ex->advance(n);
    out.slow.push_back(s.x());
    if ((n + 1) % M == 0)
      out.error =
          std::max(out.error, std::abs(s.x() - c.x_exact(2, static_cast<double>(n + 1) * h)));
  }
  out.x = {a.x(), b.x(), s.x()};
  out.fast_restarts = a.restarts;
  for (int k : log->iterations) out.outer_iterations += k;
  return out;
}

// The slow cut's coupling error falls with the slow window at the order its
// waveform degree promises (as on one rate, tests/waveform_test.cpp): the
// fine window h = 1/1024 s stays, the slow one is 4 to 32 h, and the error
// is the slow mass's distance from the single-rate run at h (itself within
// 1e-5 of the closed form), the largest at the slow windows' ends.
TEST(Multirate, EachDegreeKeepsItsOrderAcrossTheRates) {
  const double h = 1.0 / 1024;
  const std::vector<long> M = {4, 8, 16, 32};
  std::vector<double> H;
  for (long m : M) H.push_back(h * static_cast<double>(m));
  for (int p = 0; p <= Waveform::kMaxDegree; ++p) {
    const Outcome one = run_chain(p, 1, h, 1.0);
    std::vector<double> err;
    for (long m : M) {
      const Outcome multi = run_chain(p, m, h, 1.0);
      double most = 0;
      for (std::size_t n = static_cast<std::size_t>(m) - 1; n < one.slow.size();
           n += static_cast<std::size_t>(m))
        most = std::max(most, std::abs(multi.slow[n] - one.slow[n]));
      err.push_back(most);
    }
    const double order = test::fitted_order(H, err);
    // At least the promised order (a cut's own error can fall faster than
    // its leading term near M = 1, where multirate meets single rate).
    EXPECT_GE(order, p + 1.0 - 0.3) << "degree " << p << ": " << err[0] << " ... " << err.back();
    EXPECT_LE(order, p + 1.0 + 0.5) << "degree " << p << ": " << err[0] << " ... " << err.back();
    EXPECT_LT(one.error, 1e-5) << "the single-rate reference is off its closed form";
  }
}

// Implicit: the fast masses start a window again only where a slow window
// starts (the outer level's restore) or where they just were (their own
// level's), and the run repeats bit for bit.
TEST(Multirate, ImplicitStepsReRunTheFastWindowsFromTheSlowWindowsCheckpoint) {
  const long M = 8;
  const Outcome a = run_chain(1, M, 1.0 / 256, 0.25), b = run_chain(1, M, 1.0 / 256, 0.25);
  EXPECT_GT(a.outer_iterations, 2 * 0.25 * 256 / M);  // iterated: restored
  long outer = 0;
  for (const auto& [last, n] : a.fast_restarts) {
    const bool own = n == last;                                // its level's iteration
    const bool slow = n < last && n % M == 0 && last - n < M;  // the slow window's start
    outer += slow ? 1 : 0;
    EXPECT_TRUE(own || slow) << "after fine window " << last << ", started " << n << " again";
  }
  EXPECT_GT(outer, 0);
  EXPECT_EQ(a.x, b.x);  // bitwise
  EXPECT_EQ(a.fast_restarts, b.fast_restarts);
}

}  // namespace
}  // namespace railcosim::multirate_test
