#include "statics.hpp"

#include <Eigen/SparseCholesky>
#include <cmath>
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

}  // namespace

Vector solve_static(const Structure& s, const Vector& guess, double t) {
  const int n = s.layout.size;
  const bool hertz = s.contact && s.contact->law == ContactTerm::Law::kHertz;
  if (!hertz) {
    Vector u = s.load;
    if (s.contact) {
      ContactTerm::Entry g[5];
      const int ng = s.contact->entries(t, s.layout, g);
      for (int i = 0; i < ng; ++i) u[g[i].dof] -= s.contact->prescribed_force * g[i].weight;
    }
    try {
      BandCholesky(s.K).solve_in_place(u);
    } catch (const std::runtime_error&) {
      throw std::runtime_error(
          "no static equilibrium: the stiffness matrix is singular (a body is not supported)");
    }
    return u;
  }

  const ContactTerm& c = *s.contact;
  ContactTerm::Entry g[5];
  const int ng = c.entries(t, s.layout, g);
  // The sparsity pattern: the band of K plus the dense block of g g^T.
  std::vector<Eigen::Triplet<double>> base;
  const int kd = s.K.half_bandwidth();
  for (int j = 0; j < n; ++j)
    for (int i = j; i <= std::min(n - 1, j + kd); ++i)
      if (const double v = s.K(i, j); v != 0.0) base.emplace_back(i, j, v);
  // A tangent floor where the contact is open or barely closed: the slope of
  // the Hertz law at the penetration that would carry the largest load. It
  // only shapes the first iterations; the root is the same.
  const double load_scale = s.load.cwiseAbs().maxCoeff();
  const double floor_slope =
      load_scale > 0
          ? 1.5 * c.hertz_constant * std::sqrt(hertz_penetration(c.hertz_constant, load_scale))
          : 0.0;

  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  Eigen::SparseMatrix<double> A(n, n);
  Vector u = guess.size() == n ? guess : Vector::Zero(n);
  Vector r(n);
  for (int it = 0; it < kNewtonIterations; ++it) {
    double delta = c.delta0();
    for (int i = 0; i < ng; ++i) delta += g[i].weight * u[g[i].dof];
    const double F = hertz_force(c.hertz_constant, delta);
    const double slope =
        std::max(delta > 0 ? 1.5 * c.hertz_constant * std::sqrt(delta) : 0.0, floor_slope);
    r = s.load;
    s.K.multiply_add(-1.0, u, r);
    for (int i = 0; i < ng; ++i) r[g[i].dof] -= F * g[i].weight;

    std::vector<Eigen::Triplet<double>> trip = base;
    for (int a = 0; a < ng; ++a)
      for (int b = 0; b < ng; ++b)
        if (g[a].dof >= g[b].dof)
          trip.emplace_back(g[a].dof, g[b].dof, slope * g[a].weight * g[b].weight);
    A.setFromTriplets(trip.begin(), trip.end());
    if (it == 0) ldlt.analyzePattern(A);
    ldlt.factorize(A);
    if (ldlt.info() != Eigen::Success)
      throw std::runtime_error("no static equilibrium: the tangent stiffness is singular");
    const Vector du = ldlt.solve(r);
    u += du;
    if (!u.allFinite())
      throw std::runtime_error("no static equilibrium: the contact iteration ran away");
    const double step = du.cwiseAbs().maxCoeff();
    if (step <= kNewtonTolerance * u.cwiseAbs().maxCoeff()) return u;
  }
  throw std::runtime_error("no static equilibrium: the contact iteration did not converge in " +
                           std::to_string(kNewtonIterations) + " Newton steps");
}

}  // namespace railcosim
