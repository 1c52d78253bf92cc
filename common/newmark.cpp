#include "newmark.hpp"

#include <Eigen/Dense>
#include <array>
#include <cmath>

#include "hertz.hpp"
#include "work_budget.hpp"

namespace railcosim {

Newmark::Newmark(Structure& system, double interval, double tolerance, int fixed_level,
                 long max_steps_per_interval, int fixed_steps)
    : sys_(system),
      interval_(interval),
      tol_(tolerance),
      fixed_level_(fixed_level),
      max_steps_(max_steps_per_interval),
      fixed_steps_(fixed_steps),
      keff_(kMaxLevel + 2),
      responses_(kMaxLevel + 2),
      mass_(system.M) {
  const int n = sys_.layout.size;
  state_.u = Vector::Zero(n);
  state_.v = Vector::Zero(n);
  state_.a = Vector::Zero(n);
  origin_ = Vector::Zero(n);
  origin_load_ = Vector::Zero(n);
  state_.level = fixed_level;
  // A rotation error is weighed as the displacement it makes over one rail
  // element, so the tolerance means metres for every DOF.
  for (auto& cache : responses_)
    cache.entries.resize(8 * std::max<std::size_t>(1, sys_.contacts.size()));
  error_weight_ = Vector::Ones(n);
  for (int dof : sys_.layout.rail_theta) error_weight_[dof] = sys_.layout.element_length;
}

const BandCholesky& Newmark::factor(int level) {
  BandCholesky& f = keff_[level];
  if (f.empty()) {
    const double h = step_length(level);
    f = BandCholesky(SymmetricBandMatrix::combine(1.0, sys_.K, kGamma / (kBeta * h), sys_.C,
                                                  1.0 / (kBeta * h * h), sys_.M));
  }
  return f;
}

const Vector& Newmark::unit_response(int level, int dof) {
  auto& cache = responses_[level];
  for (const auto& r : cache.entries)
    if (r.dof == dof) return r.column;
  auto& slot = cache.entries[cache.next];
  cache.next = (cache.next + 1) % cache.entries.size();
  slot.dof = dof;
  slot.column.setZero(sys_.layout.size);
  slot.column[dof] = 1.0;
  factor(level).solve_in_place(slot.column);
  return slot.column;
}

double Newmark::contact_force(const Vector& u, double t) const {
  double sum = 0.0;
  for (std::size_t k = 0; k < sys_.contacts.size(); ++k) sum += contact_force(u, t, k);
  return sum;
}

double Newmark::contact_force(const Vector& u, double t, std::size_t k) const {
  const ContactTerm& c = sys_.contacts[k];
  if (c.law == ContactTerm::Law::kPrescribed) return c.prescribed_at(t);
  ContactTerm::Entry g[5];
  const int ng = c.entries(t, sys_.layout, g);
  double delta = c.delta0_at(t);
  for (int i = 0; i < ng; ++i) delta += g[i].weight * u[g[i].dof];
  return hertz_force(c.hertz_constant, delta);
}

void Newmark::set_state(const Vector& u, const Vector& v, double t) {
  state_.u = u;
  state_.v = v;
  origin_ = u;
  origin_load_.setZero(u.size());
  sys_.K.multiply_add(-1.0, origin_, origin_load_);
  update_acceleration(t);
}

void Newmark::update_acceleration(double t) {
  if (input_hook_) input_hook_(t);
  Vector r;
  sys_.load_at(t, r);
  sys_.K.multiply_add(-1.0, state_.u, r);
  sys_.C.multiply_add(-1.0, state_.v, r);
  state_.contact_force = 0.0;
  for (std::size_t k = 0; k < sys_.contacts.size(); ++k) {
    const double F = contact_force(state_.u, t, k);
    state_.contact_force += F;
    ContactTerm::Entry g[5];
    const int ng = sys_.contacts[k].entries(t, sys_.layout, g);
    for (int i = 0; i < ng; ++i) r[g[i].dof] -= F * g[i].weight;
  }
  mass_.solve_in_place(r);
  state_.a = r;
}

void Newmark::step(double t_end, double h, int level, Trial& out) {
  if (input_hook_) input_hook_(t_end);
  const double c0 = 1.0 / (kBeta * h * h), c1 = kGamma / (kBeta * h);
  const NewmarkState& s = state_;
  // The step is solved for the displacement from origin_ (the state set
  // last), not for u itself: a+ = c0 (u+ - pred_u) divides the rounding of
  // the solved vector by beta h^2, and a vehicle body hanging 0.17 m down
  // on its springs would otherwise give its acceleration a rounding error
  // of eps 0.17 m / (beta h^2), enough at small steps to drift the body
  // and keep a run from converging as the tolerance tightens.
  // Predictors: the parts of u+ and v+ known before a+.
  pred_u_ = (s.u - origin_) + h * s.v + (h * h * (0.5 - kBeta)) * s.a;
  pred_v_ = s.v + (h * (1.0 - kGamma)) * s.a;
  // K_eff u+ = load + M c0 pred_u + C (c1 pred_u - pred_v) - F g, all
  // displacements from origin_ (so the load loses K origin_).
  // The load at t_end, less K origin_ (one pass; load_at then += is the same
  // sum element by element).
  if (sys_.load_rate.size() > 0)
    rhs_ = sys_.load + (t_end - sys_.load_time) * sys_.load_rate + origin_load_;
  else
    rhs_ = sys_.load + origin_load_;
  damp_arg_ = c1 * pred_u_ - pred_v_;
  SymmetricBandMatrix::multiply_add2(c0, sys_.M, pred_u_, 1.0, sys_.C, damp_arg_, rhs_);

  const BandCholesky& keff = factor(level);
  double force = 0.0;
  if (sys_.contacts.size() > 1) {
    force = step_contacts(t_end, level);
  } else if (!sys_.contacts.empty()) {
    const ContactTerm& c = sys_.contacts.front();
    ContactTerm::Entry g[5];
    const int ng = c.entries(t_end, sys_.layout, g);
    if (c.law == ContactTerm::Law::kPrescribed) {
      force = c.prescribed_at(t_end);
      for (int i = 0; i < ng; ++i) rhs_[g[i].dof] -= force * g[i].weight;
      keff.solve_in_place(rhs_);
    } else {
      keff.solve_in_place(rhs_);  // u0: the step without contact force
      // y = K_eff^-1 g, from the cached unit responses of the <= 5 DOFs of g.
      y_.setZero(sys_.layout.size);
      for (int i = 0; i < ng; ++i) y_ += g[i].weight * unit_response(level, g[i].dof);
      double d0 = c.delta0_at(t_end), flex = 0.0;
      for (int i = 0; i < ng; ++i) {
        d0 += g[i].weight * (rhs_[g[i].dof] + origin_[g[i].dof]);
        flex += g[i].weight * y_[g[i].dof];
      }
      const double delta = hertz_solve_penetration(c.hertz_constant, d0, flex);
      force = hertz_force(c.hertz_constant, delta);
      rhs_ -= force * y_;
    }
  } else {
    keff.solve_in_place(rhs_);
  }
  out.a = c0 * (rhs_ - pred_u_);
  out.v = pred_v_ + (kGamma * h) * out.a;
  out.u = rhs_ + origin_;
  out.force = force;
}

double Newmark::step_contacts(double t_end, int level) {
  // rhs_ holds the right-hand side of the step; on return, u+ - origin_.
  const std::size_t n = sys_.contacts.size();
  const BandCholesky& keff = factor(level);
  double total = 0.0;
  if (sys_.contacts.front().law == ContactTerm::Law::kPrescribed) {
    for (const ContactTerm& c : sys_.contacts) {
      ContactTerm::Entry g[5];
      const int ng = c.entries(t_end, sys_.layout, g);
      const double F = c.prescribed_at(t_end);
      for (int i = 0; i < ng; ++i) rhs_[g[i].dof] -= F * g[i].weight;
      total += F;
    }
    keff.solve_in_place(rhs_);
    return total;
  }
  keff.solve_in_place(rhs_);  // u0: the step without contact forces
  ys_.resize(n);
  std::vector<std::array<ContactTerm::Entry, 5>> gs(n);
  std::vector<int> ngs(n);
  std::vector<double> d0(n);
  for (std::size_t k = 0; k < n; ++k) {
    const ContactTerm& c = sys_.contacts[k];
    ngs[k] = c.entries(t_end, sys_.layout, gs[k].data());
    ys_[k].setZero(sys_.layout.size);
    for (int i = 0; i < ngs[k]; ++i)
      ys_[k] += gs[k][static_cast<std::size_t>(i)].weight *
                unit_response(level, gs[k][static_cast<std::size_t>(i)].dof);
    d0[k] = c.delta0_at(t_end);
    for (int i = 0; i < ngs[k]; ++i) {
      const int dof = gs[k][static_cast<std::size_t>(i)].dof;
      d0[k] += gs[k][static_cast<std::size_t>(i)].weight * (rhs_[dof] + origin_[dof]);
    }
  }
  // Flexibility between the contacts: c_jk = g_j . K_eff^-1 g_k.
  Eigen::MatrixXd flex(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t k = 0; k < n; ++k) {
      double s = 0;
      for (int i = 0; i < ngs[j]; ++i)
        s += gs[j][static_cast<std::size_t>(i)].weight *
             ys_[k][gs[j][static_cast<std::size_t>(i)].dof];
      flex(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k)) = s;
    }
  const std::vector<double> F = hertz_solve_coupled(
      sys_.contacts.front().hertz_constant, d0, [&](std::size_t a, std::size_t b) {
        return flex(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
      });
  if (F.size() != n)
    throw StepFailure("the contact forces of the " + std::to_string(n) +
                      " wheels did not settle at t = " + std::to_string(t_end) + " s");
  for (std::size_t k = 0; k < n; ++k) {
    rhs_ -= F[k] * ys_[k];
    total += F[k];
  }
  return total;
}

double Newmark::step_length(int level) const {
  return level <= kMaxLevel ? std::ldexp(interval_, -level) : interval_ / fixed_steps_;
}

void Newmark::advance_fixed(double t0, double t1) {
  const double h = step_length(kMaxLevel + 1);
  for (int j = 1; j <= fixed_steps_; ++j) {
    if ((j & 15) == 0) {
      if (std::string why = work_budget_exceeded(); !why.empty()) throw StepFailure(why);
      work_progress(16);
    }
    const double t_next = j == fixed_steps_ ? t1 : t0 + (t1 - t0) * j / fixed_steps_;
    step(t_next, h, kMaxLevel + 1, trial_);
    std::swap(state_.u, trial_.u);
    std::swap(state_.v, trial_.v);
    std::swap(state_.a, trial_.a);
    state_.contact_force = trial_.force;
    ++state_.micro_steps;
    if (observer_) observer_(t_next, kMaxLevel + 1);
  }
}

void Newmark::advance(double t0, double t1) {
  if (fixed_steps_ > 0) {
    advance_fixed(t0, t1);
    return;
  }
  // Position inside [t, t + H] in units of H / 2^kMaxLevel.
  const long long end = 1LL << kMaxLevel;
  long long pos = 0;
  int level = tol_ > 0.0 ? state_.level : fixed_level_;
  // A level too coarse for the alignment at pos = 0 cannot happen (0 is
  // aligned with every level), so only levels are adjusted below.
  const double err_scale = std::abs(kBeta - 1.0 / 6.0);
  long attempts = 0;
  while (pos < end) {
    // The node's time budget for a step, looked at every 16 micro steps.
    if ((attempts & 15) == 15) {
      if (std::string why = work_budget_exceeded(); !why.empty()) throw StepFailure(why);
      work_progress(16);
    }
    if (++attempts > max_steps_)
      throw StepFailure("the integrator needed more than " + std::to_string(max_steps_) +
                        " micro steps to cover [" + std::to_string(t0) + ", " + std::to_string(t1) +
                        "] s: the solution is running away");
    const double h = std::ldexp(interval_, -level);
    const long long stride = 1LL << (kMaxLevel - level);
    const double t_next =
        pos + stride == end
            ? t1
            : t0 + interval_ * std::ldexp(static_cast<double>(pos + stride), -kMaxLevel);
    step(t_next, h, level, trial_);

    // Without a tolerance every step is accepted (fixed step).
    const double err =
        tol_ > 0.0
            ? err_scale * h * h *
                  (trial_.a - state_.a).cwiseAbs().cwiseProduct(error_weight_).maxCoeff() / tol_
            : 0.0;
    if (err > 1.0 && level < kMaxLevel) {
      ++level;
      ++state_.rejected_steps;
      continue;
    }
    pos += stride;
    std::swap(state_.u, trial_.u);
    std::swap(state_.v, trial_.v);
    std::swap(state_.a, trial_.a);
    state_.contact_force = trial_.force;
    ++state_.micro_steps;
    if (observer_) observer_(t_next, level);
    // Coarsen when the error is small and the next step stays aligned.
    if (tol_ > 0.0 && err < 1.0 / 16.0 && level > 0 && (pos % (2 * stride)) == 0) --level;
  }
  if (tol_ > 0.0) state_.level = level;
}

}  // namespace railcosim
