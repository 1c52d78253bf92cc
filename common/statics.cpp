#include "statics.hpp"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "hertz.hpp"

namespace railcosim {
namespace {

// Newton stops after a correction that changed no DOF by more than this
// fraction of the largest displacement: convergence being quadratic, what is
// left is then rounding (the next correction is ~1e-14 of the solution,
// which is as close as the solves themselves get).
constexpr double kNewtonTolerance = 1e-12;
constexpr int kNewtonIterations = 100;
// A soft suspension over a stiff track (a car's springs are 1e-4 of the
// rail's stiffness) turns the round-off of the residual into corrections
// above kNewtonTolerance: after kStallAfter iterations, a correction below
// kStallTolerance that is no longer halving is that floor, and the
// iteration stops there.
constexpr int kStallAfter = 10;
constexpr double kStallTolerance = 1e-9;

// Without the Hertz law (prescribed contact forces, or no contact): one
// linear solve of K u = load - the contacts' forces.
Vector solve_linear(const Structure& s, double t) {
  Vector u = s.load;
  for (const ContactTerm& c : s.contacts) {
    ContactTerm::Entry g[5];
    const int ng = c.entries(t, s.layout, g);
    for (int i = 0; i < ng; ++i) u[g[i].dof] -= c.prescribed_force * g[i].weight;
  }
  try {
    BandCholesky(s.K).solve_in_place(u);
  } catch (const std::runtime_error&) {
    throw std::runtime_error(
        "no static equilibrium: the stiffness matrix is singular (a body is not supported)");
  }
  return u;
}

// A contact's g vector at time t.
struct Contact {
  ContactTerm::Entry g[5];
  int ng = 0;
  double delta0 = 0;
};

std::vector<Contact> contacts_at(const Structure& s, double t) {
  std::vector<Contact> cs(s.contacts.size());
  for (std::size_t k = 0; k < cs.size(); ++k) {
    cs[k].ng = s.contacts[k].entries(t, s.layout, cs[k].g);
    cs[k].delta0 = s.contacts[k].static_delta0(t);
  }
  return cs;
}

// The lower band of K as triplets: with the contacts' dense g g^T blocks,
// the sparsity pattern of the tangent.
std::vector<Eigen::Triplet<double>> stiffness_triplets(const SymmetricBandMatrix& K, int n) {
  std::vector<Eigen::Triplet<double>> base;
  const int kd = K.half_bandwidth();
  for (int j = 0; j < n; ++j)
    for (int i = j; i <= std::min(n - 1, j + kd); ++i)
      if (const double v = K(i, j); v != 0.0) base.emplace_back(i, j, v);
  return base;
}

// The Hertz law as the Newton iteration uses it.
struct ContactLaw {
  double K_H = 0;
  // A tangent floor where a contact is open or barely closed: the slope of
  // the law at the penetration that would carry the largest load. It only
  // shapes the first iterations; the root is the same.
  double floor_delta = 0, floor_slope = 0;
  // Open contacts linearised about the floor's penetration.
  bool lift = false;
};

// Adds every contact's force to the residual r and its tangent to trip, at u.
void add_contacts(const std::vector<Contact>& cs, const ContactLaw& law, const Vector& u, Vector& r,
                  std::vector<Eigen::Triplet<double>>& trip) {
  const double K_H = law.K_H;
  for (const Contact& c : cs) {
    double delta = c.delta0;
    for (int i = 0; i < c.ng; ++i) delta += c.g[i].weight * u[c.g[i].dof];
    double F = hertz_force(K_H, delta);
    const double slope = std::max(delta > 0 ? 1.5 * K_H * std::sqrt(delta) : 0.0, law.floor_slope);
    if (law.lift && delta < 0) {
      // An open contact: linearise the law about the floor's penetration,
      // so that one step closes a gap of any width (the plain floor slope
      // crawls across it by load / slope per iteration).
      F = hertz_force(K_H, law.floor_delta) + law.floor_slope * (delta - law.floor_delta);
    }
    for (int i = 0; i < c.ng; ++i) r[c.g[i].dof] -= F * c.g[i].weight;
    for (int a = 0; a < c.ng; ++a)
      for (int b = 0; b < c.ng; ++b)
        if (c.g[a].dof >= c.g[b].dof)
          trip.emplace_back(c.g[a].dof, c.g[b].dof, slope * c.g[a].weight * c.g[b].weight);
  }
}

ContactLaw contact_law(const Structure& s, std::size_t contacts) {
  ContactLaw law;
  law.K_H = s.contacts.front().hertz_constant;
  const double load_scale = s.load.cwiseAbs().maxCoeff();
  law.floor_delta = load_scale > 0 ? hertz_penetration(law.K_H, load_scale) : 0.0;
  law.floor_slope = 1.5 * law.K_H * std::sqrt(law.floor_delta);
  // Several wheels, or a rail profile or flat, can open a contact by
  // millimetres at the first iterate; the single wheel on a smooth rail
  // keeps the plain floor (its static states are pinned by the regression
  // fixture of the paper's cases).
  law.lift = contacts > 1;
  for (const ContactTerm& c : s.contacts) law.lift = law.lift || c.excitation.any();
  return law;
}

}  // namespace

Vector solve_static(const Structure& s, const Vector& guess, double t) {
  const int n = s.layout.size;
  const bool hertz = !s.contacts.empty() && s.contacts.front().law == ContactTerm::Law::kHertz;
  if (!hertz) return solve_linear(s, t);
  const std::vector<Contact> cs = contacts_at(s, t);
  const std::vector<Eigen::Triplet<double>> base = stiffness_triplets(s.K, n);
  const ContactLaw law = contact_law(s, cs.size());

  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  Eigen::SparseMatrix<double> A(n, n);
  Vector u = guess.size() == n ? guess : Vector::Zero(n);
  Vector r(n);
  double last_step = std::numeric_limits<double>::infinity();
  for (int it = 0; it < kNewtonIterations; ++it) {
    r = s.load;
    s.K.multiply_add(-1.0, u, r);
    std::vector<Eigen::Triplet<double>> trip = base;
    add_contacts(cs, law, u, r, trip);
    A.setFromTriplets(trip.begin(), trip.end());
    if (it == 0) ldlt.analyzePattern(A);
    ldlt.factorize(A);
    if (ldlt.info() != Eigen::Success)
      throw std::runtime_error("no static equilibrium: the tangent stiffness is singular");
    const Vector du = ldlt.solve(r);
    u += du;
    if (!u.allFinite())
      throw std::runtime_error("no static equilibrium: the contact iteration ran away");
    const double step = du.cwiseAbs().maxCoeff(), size = u.cwiseAbs().maxCoeff();
    if (step <= kNewtonTolerance * size) return u;
    if (it >= kStallAfter && step <= kStallTolerance * size && step > 0.5 * last_step) return u;
    last_step = step;
  }
  throw std::runtime_error("no static equilibrium: the contact iteration did not converge in " +
                           std::to_string(kNewtonIterations) + " Newton steps");
}

}  // namespace railcosim
