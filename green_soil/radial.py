"""The surface's radial displacement under a vertical point load on a
layered half-space, and its x and y components beside a loaded footprint
(point_means): the horizontal component the receivers lack so far,
from the same direct-stiffness flexibility (spectral.py) at little extra
cost (the off-diagonal term of the same 2 x 2 surface flexibility, and a
J1 instead of a J0 Hankel transform on the same wavenumber grid).

With the plane-strain factor exp(-i k x), the surface displacement u_x
under a vertical stress p_z is G_xz(k, w) p_z; the axisymmetric radial
displacement of a point load is (Kausel & Roesset 1981; greens.py)

    u_r(r, w) = 1/(2 pi) int_0^inf H(k, w) J1(k r) k dk,   H = -i G_xz,

positive away from the load for a load positive down. H tends to the top
layer's static half-space value H_s = -(1 - 2 nu)/(2 mu* k) at large k,
whose transform is Boussinesq's radial displacement -(1 - 2 nu)/(4 pi mu* r)
(the surface moves toward the load). As in greens.py the integral is
taken of H - H_s, on the same wavenumber grid, with the dynamic remainder
beyond k_max taken as C k^-3, whose J1 transform is known in closed form.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import special

from .greens import Discretisation, k_grid
from .spectral import _inv2, layer_stiffness, moduli


def radial_flexibility(layers, k, w):
    """H(k, w) = -i G_xz: the radial displacement's transform per unit
    vertical surface stress (k > 0 at w = 0)."""
    k = np.asarray(k, dtype=float)
    z = layer_stiffness(layers[-1], k, w, half_space=True)
    for layer in reversed(layers[:-1]):
        kl = layer_stiffness(layer, k, w)
        k11, k12, k21, k22 = kl[:, :2, :2], kl[:, :2, 2:], kl[:, 2:, :2], kl[:, 2:, 2:]
        z = k11 - k12 @ _inv2(k22 + z) @ k21
    return -1j * _inv2(z)[:, 0, 1]


def top_radial_static(layers, w=0.0):
    """-(1 - 2 nu)/(2 mu*) of the top layer: k H_s."""
    mu, _, _ = moduli(layers[0], w)
    return -(1.0 - 2.0 * layers[0].poisson) / (2.0 * mu)


def tail_integral_j1(r, k_max):
    """int_{k_max}^inf J1(k r) k^-2 dk = r I(k_max r), with
    2 I(X) = J1(X)/X + int_X^inf J0(t)/t dt (by parts, J1' = J0 - J1/x) and
    int_X^inf J0(t)/t dt = int_0^X (1 - J0(t))/t dt - ln(X/2) - gamma."""
    r = np.asarray(r, dtype=float)
    out = np.zeros(r.shape)
    pos = r > 0
    x = k_max * r[pos]
    j0_tail = special.it2j0y0(x)[0] - np.log(x / 2.0) - np.euler_gamma
    out[pos] = r[pos] * 0.5 * (special.j1(x) / x + j0_tail)
    return out


def smooth_part(layers, omegas, r, d: Discretisation = Discretisation(), block=256,
                f_grid=None):
    """u_r - u_r,s (n_r, n_w): the radial displacement minus the top layer's
    Boussinesq value, on greens.smooth_part's wavenumber grid (that of the
    highest frequency f_grid, Hz; default the highest of omegas)."""
    f_max = max(abs(np.real(w)) for w in omegas) / (2.0 * math.pi)
    f_max = f_max if f_grid is None else f_grid
    dk_max, k_max = d.grid_limits(layers, max(f_max, 1.0), float(np.max(r)))
    k, wk = k_grid(d, dk_max, k_max)
    spec = np.empty((len(k), len(omegas)), complex)
    tail = np.empty(len(omegas), complex)
    for j, w in enumerate(omegas):
        top = top_radial_static(layers, w)
        if w == 0:  # the static basis degenerates at k = 0: extrapolate k (H - H_s)
            spec[1:, j] = k[1:] * radial_flexibility(layers, k[1:], w) - top
            spec[0, j] = 2.0 * spec[1, j] - spec[2, j]
        else:
            spec[:, j] = k * radial_flexibility(layers, k, w) - top  # k (H - H_s)
        # The dynamic remainder C k^-3 beyond k_max (the layers' own static
        # part falls exponentially with k).
        h0 = (radial_flexibility(layers, k[-1:], 0.0)[0] * top / top_radial_static(layers))
        tail[j] = k_max**2 * (spec[-1, j] + top - k_max * h0)
    spec *= wk[:, None] / (2.0 * math.pi)
    out = np.empty((len(r), len(omegas)), complex)
    for i in range(0, len(r), block):
        j1 = special.j1(np.outer(r[i:i + block], k))
        out[i:i + block] = j1 @ spec.real + 1j * (j1 @ spec.imag)
    out += np.outer(tail_integral_j1(r, k_max), tail) / (2.0 * math.pi)
    return out


def point(layers, omegas, r, d: Discretisation = Discretisation()):
    """u_r(r, w) (n_r, n_w) of a unit vertical point load, r > 0."""
    r = np.asarray(r, dtype=float)
    bous = np.array([top_radial_static(layers, w) for w in omegas]) / (2.0 * math.pi)
    return smooth_part(layers, omegas, r, d) + np.outer(1.0 / r, bous)


def _means(args):
    """The horizontal displacement (x, y) at points offset (dx, dy) from the
    centre of a loaded a x b footprint (unit force spread uniformly), for
    one block of frequencies: the radial displacement of each Gauss point's
    share, along the line from it to the point. Top-level, for workers."""
    from scipy import interpolate

    from .greens import box_rule

    layers, fp, offsets, omegas, d, f_grid = args
    a, b = fp.along, fp.across
    reach = max([math.hypot(abs(x) + a, abs(y) + b) for x, y in offsets] + [1.0])
    r = np.arange(0.0, reach + 4.0 * d.dr, d.dr)
    spline = interpolate.CubicSpline(r, smooth_part(layers, omegas, r, d, f_grid=f_grid), axis=0)
    bous = np.array([top_radial_static(layers, w) for w in omegas]) / (2.0 * math.pi)
    px, wx = box_rule(a, d.quad_along)
    py, wy = box_rule(b, d.quad_across)
    wq = np.outer(wx, wy).ravel()
    out = np.empty((2, len(offsets), len(omegas)), complex)
    gx, gy = (g.ravel() for g in np.meshgrid(px, py, indexing="ij"))
    for i, (dx, dy) in enumerate(offsets):
        ex, ey = dx - gx, dy - gy  # from each Gauss point to the point
        rho = np.maximum(np.hypot(ex, ey), 1e-9)
        u = spline(rho) + np.outer(1.0 / rho, bous)  # (points, n_w)
        out[0, i] = (wq * ex / rho) @ u
        out[1, i] = (wq * ey / rho) @ u
    return out


def point_means(layers, fp, offsets, omegas, d: Discretisation = Discretisation(), workers=1):
    """(2, n_points, n_w): the x and y displacement at points offset (dx, dy)
    from a loaded footprint's centre, at complex circular frequencies;
    `workers` processes take blocks of frequencies (greens' radial grid
    and wavenumber grid of the highest frequency for every block)."""
    from .responses import worker_count, worker_pool

    omegas = np.asarray(omegas, dtype=complex)
    if not len(offsets) or not len(omegas):
        return np.zeros((2, len(offsets), len(omegas)), complex)
    f_grid = float(np.max(np.abs(omegas.real))) / (2.0 * math.pi)
    workers = worker_count(workers)
    blocks = [blk for blk in np.array_split(np.arange(len(omegas)), max(1, workers)) if len(blk)]
    jobs = [(layers, fp, list(offsets), omegas[blk], d, f_grid) for blk in blocks]
    if len(jobs) > 1:
        with worker_pool(len(jobs)) as pool:
            parts = pool.map(_means, jobs, chunksize=1)
    else:
        parts = [_means(job) for job in jobs]
    return np.concatenate(parts, axis=2)
