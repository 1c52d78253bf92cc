"""Lamb's problem for a point load: the closed form of Pekeris (1955) for the
surface vertical displacement of a homogeneous elastic half-space with
Poisson ratio 1/4 under a vertical point force with Heaviside (step) time
dependence, and its convolution with a smooth force history.

C. L. Pekeris, "The seismic surface pulse", Proc. Natl. Acad. Sci. USA 41
(1955) 469-480. The derivation here is our own (Cagniard-de Hoop), written
out below so that the constants can be checked; it reproduces Pekeris'
structure: zero before the P wave, a smooth part between the P and S
arrivals, an inverse-square-root singularity just before the Rayleigh
arrival and the static (Boussinesq) value F (1 - nu)/(2 pi mu r) exactly
from the Rayleigh arrival on.

Signs: the force and the displacement are positive DOWN (into the
half-space), as the product's footprint forces and outputs.

Derivation (units c_S = 1, slowness p, x = p^2, a^2 = (c_S/c_P)^2 = 1/3).
The surface displacement in the Hankel-Laplace domain under a downward
step force F H(t) is w(k, s) = F/(2 pi mu s) * s^2 nu_P / R, R =
(2k^2 + s^2)^2 - 4 k^2 nu_P nu_S, nu = sqrt(k^2 + s^2 c^-2). With
J0(z) = (2/pi) int_1^inf sin(z v)/sqrt(v^2 - 1) dv and the wavenumber path
turned onto the imaginary slowness axis, the Laplace integral inverts to

    w(t) = -F/(pi^2 mu r) * int_a^tau p Im f(p) / sqrt(tau^2 - p^2) dp,

tau = c_S t / r, f = eta_a / R(ip), eta_a = sqrt(a^2 - p^2) (= i sqrt(p^2 -
a^2) beyond a). With D(x) = (1 - 2x)^4 - 16 x^2 (x - a^2)(x - 1):
  Im f = sqrt(x - a^2) (1 - 2x)^2 / D(x)                      (a < p < 1),
  Im f = sqrt(x - a^2) [(1 - 2x)^2 + 4x sqrt(x - a^2) sqrt(x - 1)] / D(x)
                                                               (p > 1),
the Rayleigh pole (D = 0 at x = gamma^2 > 1) taken as a principal value.
For nu = 1/4, D = -(32/3)(x - 1/4)(x - (3 - sqrt 3)/4)(x - (3 + sqrt 3)/4):
the last root is the Rayleigh slowness, gamma^2 = (3 + sqrt 3)/4,
c_R/c_S = 1/gamma = 0.91940. Partial fractions (1 - 2x)^2/D = sum
c_i/(x - x_i), 4x (x - a^2)/D = sum e_i/(x - x_i) and

    int_al^T sqrt(x - al) / ((x - c) sqrt(T - x)) dx
        = pi (1 - sqrt((c - al)/(c - T)))   (c outside [al, T]),
        = pi                                 (c inside, principal value)

give the closed form (x = p^2 turns p dp into dx/2, T = tau^2):

    w = -F/(2 pi mu r) [sum_i c_i (1 - sqrt((x_i - a^2)/(x_i - T)))
                        + H(T - 1) sum_i e_i (1 - sqrt((x_i - 1)/(x_i - T)))],

each bracket term equal to c_i (e_i) alone once T > x_i. Written out,
with g = gamma^2 = (3 + sqrt 3)/4 (Pekeris' explicit form), w / (F/(pi mu r)) is
  0                                                          (tau < 1/sqrt 3),
  (1/32) [6 - sqrt 3 / sqrt(tau^2 - 1/4)
          + sqrt(3 sqrt 3 - 5) / sqrt(tau^2 - (3 - sqrt 3)/4)
          - sqrt(3 sqrt 3 + 5) / sqrt(g - tau^2)]             (1/sqrt 3 < tau < 1),
  (1/16) [6 - sqrt(3 sqrt 3 + 5) / sqrt(g - tau^2)]           (1 < tau < gamma),
  3/8                                                        (tau > gamma).
tests/fe_soil/test_lamb.py checks the code against these, against a direct
quadrature of the integral above, the Boussinesq limit and the arrivals.
"""
from __future__ import annotations

import math

import numpy as np

A2 = 1.0 / 3.0  # (c_S/c_P)^2 for nu = 1/4
ROOTS = np.array([0.25, (3.0 - math.sqrt(3.0)) / 4.0, (3.0 + math.sqrt(3.0)) / 4.0])
GAMMA2 = ROOTS[2]  # Rayleigh slowness squared (c_S/c_R)^2
RAYLEIGH_RATIO = 1.0 / math.sqrt(GAMMA2)  # c_R/c_S = 0.919402


def _d_prime(x):
    """D'(x) at a root of D(x) = -(32/3) prod (x - x_i)."""
    others = [r for r in ROOTS if abs(r - x) > 1e-12]
    return -(32.0 / 3.0) * (x - others[0]) * (x - others[1])


C = np.array([(1.0 - 2.0 * x) ** 2 / _d_prime(x) for x in ROOTS])
E = np.array([4.0 * x * (x - A2) / _d_prime(x) for x in ROOTS])


def _k(c, alpha, T):
    """(1/pi) int_alpha^T sqrt(x - alpha)/((x - c) sqrt(T - x)) dx for
    T >= alpha (a principal value once alpha < c < T); 0 for T < alpha."""
    T = np.asarray(T, dtype=float)
    Tc = np.maximum(T, alpha)
    if c < alpha:
        out = 1.0 - np.sqrt((alpha - c) / (Tc - c))
    else:
        out = np.ones_like(Tc)
        before = Tc < c
        out[before] = 1.0 - np.sqrt((c - alpha) / (c - Tc[before]))
    return np.where(T > alpha, out, 0.0)


def normalized_step(tau):
    """w / (F / (pi mu r)) against tau = c_S t / r (positive down). Unbounded
    as tau -> gamma from below (an inverse square-root singularity); the
    static value 3/8 from tau = gamma on."""
    T = np.asarray(tau, dtype=float) ** 2
    bracket = np.zeros_like(T)
    for x, c, e in zip(ROOTS, C, E):
        bracket += c * _k(x, A2, T) + e * _k(x, 1.0, T)
    return -0.5 * bracket


def step_response(t, r, mu, cs, force=1.0):
    """Downward surface displacement (m) at distance r (m) and times t (s)
    under a downward step force `force` (N) at t = 0; nu = 1/4."""
    return force / (math.pi * mu * r) * normalized_step(cs * np.asarray(t, dtype=float) / r)


def static_displacement(r, mu, force=1.0, nu=0.25):
    """Boussinesq: F (1 - nu) / (2 pi mu r) at the surface."""
    return force * (1.0 - nu) / (2.0 * math.pi * mu * r)


def arrivals(r, cs):
    """(t_P, t_S, t_R) at distance r for nu = 1/4."""
    return r * math.sqrt(A2) / cs, r / cs, r / (RAYLEIGH_RATIO * cs)


def convolve(t, r, mu, cs, f, df, nodes=400):
    """int_0^inf g(s) df(t - s) ds, g the unit step response at r: the
    response to a force history F(t) is convolve(..., F, F') for the
    displacement and convolve(..., F', F'') for the velocity (the force at
    rest before t = 0). `f` (the antiderivative of `df`) gives the tail:
    from the Rayleigh arrival on g is the static value, so that part is
    g_static f(t - t_R). The singular piece [t_S, t_R] is integrated in
    s = t_R - (t_R - t_S) q^2 (the integrand is then smooth), each piece by
    Gauss-Legendre with `nodes` points. Vectorised over t."""
    t = np.asarray(t, dtype=float)[:, None]
    t_p, t_s, t_r = arrivals(r, cs)
    q, wq = np.polynomial.legendre.leggauss(nodes)
    q, wq = 0.5 * (q + 1.0), 0.5 * wq  # on [0, 1]
    s1 = t_p + (t_s - t_p) * q
    part1 = (wq * (t_s - t_p) * step_response(s1, r, mu, cs) * df(t - s1)).sum(axis=1)
    span = t_r - t_s
    s2 = t_r - span * q**2
    part2 = (wq * 2.0 * span * q * step_response(s2, r, mu, cs) * df(t - s2)).sum(axis=1)
    tail = static_displacement(r, mu) * f(t[:, 0] - t_r)
    return part1 + part2 + tail


def ricker(fc, t0):
    """A Ricker wavelet of centre frequency fc peaking at t0 (unit height),
    and its first and second derivatives, as functions of t."""
    w = math.pi * fc

    def f(t):
        th2 = (w * (t - t0)) ** 2
        return (1.0 - 2.0 * th2) * np.exp(-th2)

    def df(t):
        th = w * (t - t0)
        return w * (4.0 * th**3 - 6.0 * th) * np.exp(-th * th)

    def d2f(t):
        th2 = (w * (t - t0)) ** 2
        return w * w * (-8.0 * th2 * th2 + 24.0 * th2 - 6.0) * np.exp(-th2)

    return f, df, d2f
