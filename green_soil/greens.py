"""Surface Green's functions in space: a point load's vertical displacement
g(r, w) by the Hankel transform of the layered flexibility G(k, w)
(spectral.py), and a rectangular footprint's response averaged over a
footprint or at a point.

    g(r, w) = 1/(2 pi) int_0^inf G(k, w) J0(k r) k dk

G tends to the top layer's static half-space G_s = (1 - nu)/(mu* k) at
large k, whose transform is Boussinesq's (1 - nu)/(2 pi mu* r), singular
at r = 0. So the integral is taken of G - G_s (finite at k = 0 and
decaying like k^-3), on a wavenumber grid fine enough for the poles of the
surface waves near the real axis and for J0's oscillation at the largest
distance (`Discretisation`); beyond k_max the remainder is taken as
C(w) k^-3, C = k_max^3 (G(w) - G(0))(k_max) (the dynamic part: the
layers' static part falls exponentially), whose transform is known in
closed form (tail_integral). Boussinesq's part is averaged over the footprints in
closed form in one direction and by adaptive quadrature in the other
(static_pair, static_point); the smooth rest, g - g_s, is tabulated on a
radial grid, interpolated by cubic splines and averaged by Gauss-Legendre
quadrature over the footprints' correlation function (a tent in each
direction for two equal rectangles).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate, interpolate, special

from . import cost
from .spectral import surface_flexibility, top_static


@dataclass(frozen=True)
class Discretisation:
    """The numerical parameters (chosen by convergence: docs/green-soil.md,
    tests/green_soil/test_convergence.py). The wavenumber grid's step is
    min(max(k_ratio k, dk_min), dk_max) up to k_max: k_ratio resolves a
    surface-wave pole of width about xi k, dk_max = 2 pi / (per_period
    r_max) J0's oscillation at the farthest distance r_max (and puts the
    grid's periodic images 2 pi / dk_max away), k_max = k_max_factor times
    the top layer's shear wavenumber at f_max (and at least 8 / its
    thickness, where the layers below no longer matter)."""

    k_ratio: float = 0.004
    dk_min: float = 2e-4  # rad/m, the step near k = 0
    per_period: float = 8.0
    k_max_factor: float = 3.0
    dr: float = 0.1  # m, radial grid of g - g_s (cubic splines)
    quad_along: int = 8  # Gauss points per half tent (along the track)
    quad_across: int = 12  # per half tent across

    def key(self):
        return (self.k_ratio, self.dk_min, self.per_period, self.k_max_factor, self.dr,
                self.quad_along, self.quad_across)

    def grid_limits(self, layers, f_max, r_max):
        """(dk_max, k_max) for these layers, frequencies and distances."""
        top = layers[0]
        k_max = self.k_max_factor * 2.0 * math.pi * f_max / top.shear_speed
        if len(layers) > 1:
            k_max = max(k_max, 8.0 / top.thickness)
        return 2.0 * math.pi / (self.per_period * max(r_max, 1.0)), k_max


def k_grid(d: Discretisation, dk_max, k_max):
    """Wavenumbers from 0 to k_max, step min(max(k_ratio k, dk_min), dk_max),
    and their trapezoid weights. Refuses (ValueError) more than
    cost.MAX_WAVENUMBERS points before building any."""
    n = cost.wavenumbers(dk_max, k_max, d.k_ratio, d.dk_min)
    if not n <= cost.MAX_WAVENUMBERS:
        raise ValueError("the wavenumber grid to k_max = %.3g rad/m in steps of at most %.3g "
                         "rad/m would have %.3g points (at most %d)"
                         % (k_max, dk_max, n, cost.MAX_WAVENUMBERS))
    ks = [0.0]
    while ks[-1] < k_max:
        ks.append(ks[-1] + min(max(d.k_ratio * ks[-1], d.dk_min), dk_max))
    k = np.array(ks)
    k[-1] = k_max
    w = np.zeros_like(k)
    step = np.diff(k)
    w[:-1] += 0.5 * step
    w[1:] += 0.5 * step
    return k, w


def tail_integral(r, k_max):
    """int_{k_max}^inf J0(k r) k^-2 dk (by parts, with int_0^x J0 and J1)."""
    r = np.asarray(r, dtype=float)
    out = np.full(r.shape, 1.0 / k_max)
    pos = r > 0
    x = k_max * r[pos]
    int_j0 = special.itj0y0(x)[0]
    out[pos] = r[pos] * (special.j0(x) / x - (1.0 - int_j0 + special.j1(x)))
    return out


def smooth_part(layers, omegas, r, d: Discretisation, block=256, f_grid=None):
    """g(r, w) - g_s(r, w) (n_r, n_w): the point load's displacement minus
    the top layer's Boussinesq value, for complex circular frequencies.
    The wavenumber grid is that of the highest frequency f_grid (Hz;
    default the highest of omegas), so that a block of frequencies gets
    the same grid as the whole set."""
    f_max = max(abs(np.real(w)) for w in omegas) / (2.0 * math.pi)
    f_max = f_max if f_grid is None else f_grid
    dk_max, k_max = d.grid_limits(layers, max(f_max, 1.0), float(np.max(r)))
    k, wk = k_grid(d, dk_max, k_max)
    spec = np.empty((len(k), len(omegas)), complex)
    tail = np.empty(len(omegas), complex)
    for j, w in enumerate(omegas):
        top = top_static(layers, w)
        if w == 0:  # the static basis degenerates at k = 0: extrapolate k (G - G_s)
            spec[1:, j] = k[1:] * surface_flexibility(layers, k[1:], w) - top
            spec[0, j] = 2.0 * spec[1, j] - spec[2, j]
        else:
            spec[:, j] = k * surface_flexibility(layers, k, w) - top  # k (G - G_s)
        # The dynamic remainder C k^-3, C = k_max^3 (G(w) - G(0))(k_max): the
        # layers' own static part falls exponentially with k, not like k^-3.
        g0 = surface_flexibility(layers, k[-1:], 0.0)[0] * top / top_static(layers)
        tail[j] = k_max**2 * (spec[-1, j] + top - k_max * g0)
    spec *= wk[:, None] / (2.0 * math.pi)
    out = np.empty((len(r), len(omegas)), complex)
    for i in range(0, len(r), block):
        j0 = special.j0(np.outer(r[i:i + block], k))
        out[i:i + block] = j0 @ spec.real + 1j * (j0 @ spec.imag)
    out += np.outer(tail_integral(r, k_max), tail) / (2.0 * math.pi)
    return out


def _inner_tent(x, dy, b):
    """int (b - |s|)/b^2 / sqrt(x^2 + (dy + s)^2) ds over [-b, b]."""
    x = max(abs(x), 1e-300)
    total = 0.0
    # On [-b, 0]: weight (b + s)/b^2 = (b - dy + u)/b^2 with u = dy + s.
    # On [0, b]: (b - s)/b^2 = (b + dy - u)/b^2.
    for lo, hi, alpha, beta in ((dy - b, dy, b - dy, 1.0), (dy, dy + b, b + dy, -1.0)):
        f = lambda u: alpha * math.asinh(u / x) + beta * math.sqrt(x * x + u * u)
        total += f(hi) - f(lo)
    return total / (b * b)


def static_pair(dx, dy, a, b):
    """Boussinesq's mean displacement over an a x b rectangle (a along x)
    under a unit force spread uniformly over an equal rectangle offset by
    (dx, dy), for (1 - nu)/mu = 1."""
    pts = [p for p in (-dx,) if -a < p < a and p != 0.0]
    total = 0.0
    for lo, hi, sgn in ((-a, 0.0, 1.0), (0.0, a, -1.0)):
        inner = [p for p in pts if lo < p < hi]
        f = lambda s: (a + sgn * s) / (a * a) * _inner_tent(dx + s, dy, b)
        val, _ = integrate.quad(f, lo, hi, points=inner or None, limit=400, epsabs=0.0,
                                epsrel=1e-11)
        total += val
    return total / (2.0 * math.pi)


def static_point(dx, dy, a, b):
    """Boussinesq's displacement at a point offset (dx, dy) from the centre
    of an a x b rectangle carrying a unit force uniformly, (1 - nu)/mu = 1."""

    def f(s):
        x = max(abs(dx + s), 1e-300)
        return math.asinh((dy + 0.5 * b) / x) - math.asinh((dy - 0.5 * b) / x)

    inner = [-dx] if -0.5 * a < -dx < 0.5 * a else None
    val, _ = integrate.quad(f, -0.5 * a, 0.5 * a, points=inner, limit=400, epsabs=0.0,
                            epsrel=1e-11)
    return val / (a * b) / (2.0 * math.pi)


def tent_rule(a, n):
    """Nodes and weights of int lambda(s) f(s) ds, lambda the unit-area tent
    of half-width a: n Gauss-Legendre points on each half."""
    x, w = np.polynomial.legendre.leggauss(n)
    s = 0.5 * a * (x + 1.0)  # on [0, a]
    wt = 0.5 * a * w * (a - s) / (a * a)
    return np.concatenate([-s[::-1], s]), np.concatenate([wt[::-1], wt])


def box_rule(a, n):
    """Nodes and weights of the mean over [-a/2, a/2]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * a * x, 0.5 * w
