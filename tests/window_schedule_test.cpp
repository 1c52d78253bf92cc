// The accelerators on fixed-point problems with known solutions, and the
// window schedule's inputs (ramps, extrapolation, checkpoints) with scalar
// fake participants whose coupled step has a closed form.
#include "engine/window_schedule.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace railcosim {
namespace window_schedule_test {

using engine::Accelerator;
using engine::AcceleratorKind;
using engine::AcceleratorOptions;
using engine::CouplingMethod;
using engine::CouplingOptions;
using engine::InputMode;
using engine::make_accelerator;
using engine::make_schedule;
using engine::parse_accelerator;
using engine::Route;
using engine::Routing;
using engine::Schedule;
using engine::WindowSchedule;

using Eigen::MatrixXd;
using Eigen::VectorXd;

// Iterates x <- accelerator(x, G(x)) until ||G(x) - x|| <= tol ||G(x)||;
// returns the iterations used (max + 1 when it did not converge).
template <class G>
int iterate(Accelerator& a, VectorXd& x, G g, int max, double tol) {
  a.start_window();
  for (int k = 1; k <= max; ++k) {
    const VectorXd gx = g(x);
    if ((gx - x).norm() <= tol * gx.norm()) {
      a.end_window();
      return k;
    }
    x = a.next(x, gx);
  }
  a.end_window();
  return max + 1;
}

TEST(Accelerators, IqnIlsSolvesALinearFixedPointThatPlainIterationCannot) {
  // G(x) = A x + b with spectral radius > 1: x <- G(x) diverges. On an affine
  // map IQN-ILS is a secant method that is exact after n + 1 evaluations.
  const int n = 6;
  MatrixXd A = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    A(i, i) = 0.3 + 0.2 * i;  // up to 1.3
    if (i + 1 < n) A(i, i + 1) = 0.4;
  }
  const VectorXd b = VectorXd::LinSpaced(n, 1.0, 2.0);
  const VectorXd solution = (MatrixXd::Identity(n, n) - A).lu().solve(b);
  AcceleratorOptions o;
  o.kind = AcceleratorKind::kIqnIls;
  o.windows_reused = 0;
  auto a = make_accelerator(o, {n});
  VectorXd x = VectorXd::Zero(n);
  const int k = iterate(
      *a, x, [&](const VectorXd& v) { return VectorXd(A * v + b); }, 50, 1e-12);
  EXPECT_LE(k, n + 3);
  EXPECT_LT((x - solution).norm(), 1e-9 * solution.norm());
}

TEST(Accelerators, IqnIlsReusesPastWindows) {
  // The same affine map in a second window: with the first window's columns
  // reused, it converges in fewer iterations than from scratch.
  const int n = 6;
  MatrixXd A = MatrixXd::Identity(n, n) * 0.9;
  A(0, n - 1) = 0.5;
  auto g = [&](const VectorXd& v) { return VectorXd(A * v + VectorXd::Ones(n)); };
  AcceleratorOptions o;
  o.kind = AcceleratorKind::kIqnIls;
  o.windows_reused = 0;
  auto fresh = make_accelerator(o, {n});
  o.windows_reused = 4;
  auto reusing = make_accelerator(o, {n});
  VectorXd x = VectorXd::Zero(n), y = VectorXd::Zero(n);
  iterate(*fresh, x, g, 50, 1e-12);
  iterate(*reusing, y, g, 50, 1e-12);
  x.setZero();
  y.setZero();
  const int again_fresh = iterate(*fresh, x, g, 50, 1e-12);
  const int again_reusing = iterate(*reusing, y, g, 50, 1e-12);
  EXPECT_LT(again_reusing, again_fresh);
  EXPECT_LE(again_reusing, 2);  // the secant model is already exact
}

TEST(Accelerators, AitkenIsExactOnAScalarAffineMap) {
  // x <- a x + b with a = -3 (plain iteration diverges): Aitken's factor
  // after one secant step is 1 / (1 - a), which lands on the solution.
  auto acc = make_accelerator({AcceleratorKind::kAitken}, {1});
  VectorXd x = VectorXd::Zero(1);
  const int k = iterate(
      *acc, x, [](const VectorXd& v) { return VectorXd(-3.0 * v.array() + 8.0); }, 10, 1e-14);
  EXPECT_LE(k, 4);
  EXPECT_NEAR(x[0], 2.0, 1e-12);
}

TEST(Accelerators, ConstantRelaxationContractsByTheClosedFormFactor) {
  // x <- x + w (a x + b - x): the error shrinks by |1 - w (1 - a)| per step.
  const double a = 0.6, w = 0.5, factor = std::abs(1 - w * (1 - a));
  AcceleratorOptions o;
  o.kind = AcceleratorKind::kConstant;
  o.relaxation = w;
  auto acc = make_accelerator(o, {1});
  acc->start_window();
  VectorXd x = VectorXd::Zero(1);
  const double solution = 1.0 / (1 - a);
  double before = std::abs(x[0] - solution);
  for (int k = 0; k < 5; ++k) {
    x = acc->next(x, VectorXd::Constant(1, a * x[0] + 1.0));
    const double after = std::abs(x[0] - solution);
    EXPECT_NEAR(after / before, factor, 1e-12);
    before = after;
  }
}

TEST(Accelerators, BadOptionsAreRefusedByName) {
  AcceleratorOptions o;
  o.relaxation = 1.5;
  EXPECT_THROW(make_accelerator(o, {1}), std::invalid_argument);
  EXPECT_THROW(parse_accelerator("anderson", "--accelerator"), std::invalid_argument);
  CouplingOptions c;
  c.method = CouplingMethod::kImplicit;
  c.inputs = InputMode::kExtrapolate2;
  EXPECT_THROW(check(c), std::invalid_argument);
}

// A scalar participant: one interface, displacement in and out. A step sets
// state <- alpha * state + beta * (input at the end of the step).
class Scalar final : public Participant {
 public:
  Scalar(std::string name, double alpha, double beta, double state, std::vector<std::string>& log)
      : name_(std::move(name)), alpha_(alpha), beta_(beta), state_(state), log_(log) {}
  std::string name() const override { return name_; }
  Channels channels() const override { return {}; }
  CouplingData statics(const CouplingData&) override { return out(); }
  StepResult initialize(const CouplingData& in) override {
    end_ = in[0].displacement[0];
    return {out(), 0.0, true, {}};
  }
  void set_inputs(long n, const CouplingData& in) override {
    end_ = in[0].displacement[0];
    log_.push_back(name_ + " hold " + std::to_string(n) + " " + num(end_));
  }
  void set_inputs(long n, const CouplingData& start, const CouplingData& end) override {
    end_ = end[0].displacement[0];
    log_.push_back(name_ + " ramp " + std::to_string(n) + " " + num(start[0].displacement[0]) +
                   " " + num(end_));
  }
  CouplingData outputs() override { return out(); }
  void start_step(long) override { state_ = alpha_ * state_ + beta_ * end_; }
  StepResult finish_step() override { return {out(), 0.0, true, {}}; }
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {{state_, end_}}; }
  void restore(const ParticipantState& s) override {
    state_ = s.values[0];
    end_ = s.values[1];
    log_.push_back(name_ + " restore");
  }
  double state() const { return state_; }

 private:
  static std::string num(double v) { return std::to_string(static_cast<int>(std::lround(v))); }
  CouplingData out() const { return {InterfaceData{{state_}, {}, {}}}; }
  std::string name_;
  double alpha_, beta_, state_, end_ = 0;
  std::vector<std::string>& log_;
};

struct Pair {
  std::vector<std::string> log;
  Scalar a{"A", 0.5, 2.0, 4.0, log}, b{"B", 0.5, 0.8, 2.0, log};
  Routing routing{{Route{1, 0}}, {Route{0, 0}}};
  std::unique_ptr<Schedule> make(Scheme scheme, const CouplingOptions& o) {
    auto s = make_schedule(scheme, Feedthrough::kLagged, o, {&a, &b}, routing, {"A", "B"}, 1.0);
    s->initialize({{InterfaceData{{2.0}, {}, {}}}, {InterfaceData{{4.0}, {}, {}}}});
    return s;
  }
};

CouplingOptions implicit(AcceleratorKind kind) {
  CouplingOptions o;
  o.method = CouplingMethod::kImplicit;
  o.accelerator.kind = kind;
  o.convergence = 1e-13;
  return o;
}

TEST(WindowSchedule, ParallelImplicitReachesTheCoupledStepWhereRelaxationCannot) {
  // One window: a = 0.5 sa + 2 b, b = 0.5 sb + 0.8 a. The Jacobi iteration
  // matrix has eigenvalues +-sqrt(1.6): no relaxation factor converges, the
  // quasi-Newton method does.
  Pair p;
  auto s = p.make(Scheme::kJacobi, implicit(AcceleratorKind::kIqnIls));
  s->advance(0);
  const double a = (0.5 * 4.0 + 2.0 * 0.5 * 2.0) / (1 - 2.0 * 0.8);
  EXPECT_NEAR(p.a.state(), a, 1e-9 * std::abs(a));
  EXPECT_NEAR(p.b.state(), 0.5 * 2.0 + 0.8 * a, 1e-9 * std::abs(a));
  const auto& log = dynamic_cast<WindowSchedule&>(*s).log();
  EXPECT_LE(log.iterations.at(0), 5);
  EXPECT_EQ(log.quantities,
            (std::vector<std::string>{"B_to_A_displacement", "A_to_B_displacement"}));
  // Every iteration after the first restarts both from the checkpoint.
  EXPECT_EQ(std::count(p.log.begin(), p.log.end(), "A restore"), log.iterations[0] - 1);

  Pair q;
  CouplingOptions relaxed = implicit(AcceleratorKind::kConstant);
  relaxed.max_iterations = 30;
  auto r = q.make(Scheme::kJacobi, relaxed);
  r->advance(0);
  EXPECT_EQ(dynamic_cast<WindowSchedule&>(*r).log().not_converged, 1);
}

TEST(WindowSchedule, SerialImplicitWithAitkenAcceleratesTheUpwardValueOnly) {
  Pair p;
  auto s = p.make(Scheme::kGaussSeidel, implicit(AcceleratorKind::kAitken));
  s->advance(0);
  const double a = (0.5 * 4.0 + 2.0 * 0.5 * 2.0) / (1 - 2.0 * 0.8);
  EXPECT_NEAR(p.a.state(), a, 1e-9 * std::abs(a));
  const auto& log = dynamic_cast<WindowSchedule&>(*s).log();
  EXPECT_EQ(log.quantities, std::vector<std::string>{"B_to_A_displacement"});
  EXPECT_LE(log.iterations.at(0), 4);
}

TEST(WindowSchedule, GaussSeidelLinearRampsOnlyWhereTheEndIsKnown) {
  Pair p;
  CouplingOptions o;
  o.inputs = InputMode::kLinear;
  auto s = p.make(Scheme::kGaussSeidel, o);
  s->advance(0);
  // A steps first: B's value at the end is unknown, so A holds 2. B then
  // ramps from A's value at t = 0 (4) to A's fresh one (0.5*4 + 2*2 = 6).
  EXPECT_EQ(p.log, (std::vector<std::string>{"A hold 0 2", "B ramp 0 4 6"}));
}

TEST(WindowSchedule, ExtrapolationRampsToTheExtrapolatedValue) {
  Pair p;
  CouplingOptions o;
  o.inputs = InputMode::kExtrapolate1;
  auto s = p.make(Scheme::kJacobi, o);
  s->advance(0);  // no past point yet: held
  s->advance(1);  // A's input ramps from b1 to 2 b1 - b0
  // b0 = 2, a0 = 4; step 0: a1 = 0.5*4 + 2*2 = 6, b1 = 0.5*2 + 0.8*4 = 4.2.
  ASSERT_EQ(p.log.size(), 4u);
  EXPECT_EQ(p.log[0], "A hold 0 2");
  EXPECT_EQ(p.log[2], "A ramp 1 4 6");  // 4.2 -> 2 * 4.2 - 2 = 6.4, printed rounded
  EXPECT_EQ(p.log[3], "B ramp 1 6 8");  // 6 -> 2 * 6 - 4 = 8
}

}  // namespace window_schedule_test
}  // namespace railcosim
