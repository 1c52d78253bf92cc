// Newmark time integration with an adaptive step.
//
// Scheme: Newmark with beta = 1/4, gamma = 1/2 (average acceleration, second
// order, no numerical damping, unconditionally stable for linear systems):
//   u+ = u + h v + h^2 ((1/2 - beta) a + beta a+)
//   v+ = v + h ((1 - gamma) a + gamma a+)
//
// Each step is implicit. The linear part uses the constant band matrix
//   K_eff(h) = K + gamma/(beta h) C + 1/(beta h^2) M,
// factorised once per step size and cached. A Hertz contact is a rank-one
// term F(delta) g: with y = K_eff^-1 g the step reduces to one scalar
// equation in the penetration, solved by Newton to machine precision (with
// several wheels, one small system in their penetrations, see
// hertz_solve_coupled). y is combined from cached columns of K_eff^-1 for
// the few DOFs g touches, so a step costs one band solve, and no dense
// factorisation is ever made.
//
// Step size: h = H / 2^level inside each interval [t, t + H] requested by the
// caller (a macro step or an output step), so every requested time is hit
// exactly. The local error estimate of Newmark,
//   e = h^2 (beta - 1/6) (a+ - a),
// is compared with the tolerance in metres (a rotation's error is weighed by
// the rail element length): a step with max|e| > tol is redone with h/2; after a step with
// max|e| < tol/16 the next one may use 2h (the error is third order in h).
#pragma once

#include <array>
#include <functional>
#include <stdexcept>
#include <vector>

#include "banded_matrix.hpp"
#include "track_model.hpp"

namespace railcosim {

// The integrator could not cover an interval within its budget of micro
// steps: the solution is running away (or the inputs are absurd).
class StepFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct NewmarkState {
  Vector u, v, a;
  double contact_force = 0;  // the sum over the contact terms at the state's time
  int level = 0;             // step size H / 2^level for the next step
  long micro_steps = 0;      // accepted steps since the start
  long rejected_steps = 0;
};

class Newmark {
 public:
  static constexpr double kBeta = 0.25;
  static constexpr double kGamma = 0.5;
  static constexpr int kMaxLevel = 30;  // H / 2^30: ~1e-13 s for H = 1e-4 s
  // Default budget of micro steps (accepted or rejected) in one interval;
  // beyond it advance() throws StepFailure rather than grind on: a run that
  // needs this many is running away.
  static constexpr long kMaxStepsPerInterval = 1L << 16;

  // interval: the length H of the intervals advance() will be asked to cover.
  // A tolerance of 0 disables adaptivity (fixed step H / 2^fixed_level).
  // fixed_steps > 0: every interval is covered in exactly that many equal
  // steps, whatever the tolerance (for comparisons with solvers that do not
  // adapt).
  Newmark(Structure& system, double interval, double tolerance, int fixed_level = 0,
          long max_steps_per_interval = kMaxStepsPerInterval, int fixed_steps = 0);

  NewmarkState& state() { return state_; }
  const NewmarkState& state() const { return state_; }

  // Sets u, v and makes a consistent with the equations of motion at time t
  // (a = M^-1 (load - C v - K u - F g)). Call after the load or the held
  // values of the contact change, and at the start.
  void set_state(const Vector& u, const Vector& v, double t);
  void update_acceleration(double t);

  // Advances from t0 to t1 = t0 + H (H as given to the constructor; the
  // caller computes both ends from integer step counts, so that t1 is exact).
  void advance(double t0, double t1);

  // Called after every accepted micro step with its end time and its level
  // (step = H / 2^level). For tests and diagnostics; empty by default.
  void set_step_observer(std::function<void(double t, int level)> observer) {
    observer_ = std::move(observer);
  }

  // Called with t before the loads of time t are used (every micro step's
  // end time, and the time of update_acceleration): time-dependent inputs
  // set the system's load and held contact values there. Empty by default.
  void set_input_hook(std::function<void(double t)> hook) { input_hook_ = std::move(hook); }

  // The force of contact k for displacement u at time t.
  double contact_force(const Vector& u, double t, std::size_t k) const;
  // Their sum (0 without a contact).
  double contact_force(const Vector& u, double t) const;

 private:
  struct Trial {
    Vector u, v, a;
    double force = 0;
  };
  void step(double t_end, double h, int level, Trial& out);
  // The contact forces of a step with several contacts: turns rhs_ into u+
  // and returns the sum of the forces.
  double step_contacts(double t_end, int level);
  // The step length of a cache slot: H / 2^level, or H / fixed_steps in the
  // extra slot kMaxLevel + 1.
  double step_length(int level) const;
  void advance_fixed(double t0, double t1);
  const BandCholesky& factor(int level);
  // Column `dof` of K_eff(level)^-1. The contact moves through one rail
  // element in dozens of steps, so a few cached columns serve them all.
  const Vector& unit_response(int level, int dof);
  struct ResponseCache {
    struct Entry {
      int dof = -1;
      Vector column;
    };
    std::vector<Entry> entries;  // 8 per contact
    std::size_t next = 0;
  };

  Structure& sys_;
  double interval_;
  double tol_;
  int fixed_level_;
  long max_steps_;
  int fixed_steps_;
  NewmarkState state_;
  std::vector<BandCholesky> keff_;        // per level, made on first use
  std::vector<ResponseCache> responses_;  // per level
  BandCholesky mass_;
  Trial trial_;
  Vector pred_u_, pred_v_, damp_arg_, rhs_, y_;
  // The displacement the steps are solved from (the last set_state) and
  // -K times it.
  Vector origin_, origin_load_;
  std::vector<Vector> ys_;  // y per contact, with several contacts
  Vector error_weight_;
  std::function<void(double, int)> observer_;
  std::function<void(double)> input_hook_;
};

}  // namespace railcosim
