// The static equilibrium of one (sub)system for the values it holds: what a
// participant solves on its own, for given interface values, so that the
// coupled static state can be found through the interfaces alone.
#pragma once

#include "banded_matrix.hpp"
#include "track_model.hpp"

namespace railcosim {

// Solves K u + F(delta(u)) g = load at time t (velocities zero; the load
// includes the held interface values). Linear systems take one band solve.
// With a Hertz contact it is Newton's method on the tangent K + k_t g g^T
// (a sparse LDL^T, since g couples the wheel to rail DOFs far away in the
// numbering, and K alone is singular when the wheel rests on the contact
// only), started from `guess`, to machine precision. Throws
// std::runtime_error if there is no equilibrium (e.g. a wheel out of contact).
Vector solve_static(const Structure& system, const Vector& guess, double t = 0.0);

}  // namespace railcosim
