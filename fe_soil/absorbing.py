"""Absorbing layers: mass-proportional damping that grows from zero at the
inner face of a layer around the region of interest to its largest value
at the block's absorbing boundary (the sides and the bottom), so that what
leaves the region is damped out on its way to the boundary and back
instead of coming back.

The damping is a0(d) M with a0 = a_max (d / L)^2, d the distance past the
layer's inner face and L the layer's thickness on that side. For a wave
of angular frequency w >> a0 the amplitude decays like exp(-a0 x / (2 c))
over x metres at speed c, so a trip through the layer and back takes
exp(-a_max L / (3 c)) off it: a_max = 3 c ln(1 / R) / L makes that factor R
(the nominal reflection), with c the cell's shear-wave speed (the slowest
body wave, the one the layer must stop). The growth from zero keeps the
layer's own reflection (its impedance grows with a0 / w) small; the
Lysmer-Kuhlemeyer dashpots stay at the outer face. A mass-proportional
term is diagonal with the lumped mass and taken at the end of the step, so
it does not shorten the explicit step, and it does not enter the statics.

The method is that of absorbing layers with increasing damping (Caughey
absorbing layer method): J. F. Semblat, L. Lenti, A. Gandomzadeh, "A simple
multi-directional absorbing layer method to simulate elastic wave
propagation in unbounded domains", Int. J. Numer. Meth. Engng 85 (2011)
1543-1563; the quadratic growth as in the profiles of perfectly matched
layers (F. Collino, C. Tsogka, Geophysics 66 (2001) 294-307).
"""
from __future__ import annotations

import math

import numpy as np
import dolfinx.mesh
from dolfinx import fem


def profile(points, inner, outer):
    """The layer's depth of each point, d / L in [0, 1] (0 inside the
    region of interest): the largest over the axes. `inner` = (x_lo, x_hi,
    y_hi, z_lo), the region's faces; `outer` = (0, L, W, -D), the block's;
    |y| is measured (the full block's side y = -W mirrors y = W)."""
    x, y, z = points[:, 0], np.abs(points[:, 1]), points[:, 2]
    x_lo, x_hi, y_hi, z_lo = inner
    x0, x1, w, d = outer
    parts = []
    for dist, thick in ((x_lo - x, x_lo - x0), (x - x_hi, x1 - x_hi), (y - y_hi, w - y_hi),
                        (z_lo - z, z_lo - d)):
        parts.append(np.clip(dist, 0.0, None) / thick if thick > 0.0 else np.zeros(len(x)))
    return np.clip(np.max(parts, axis=0), 0.0, 1.0)


def thickness(points, inner, outer):
    """L of the side each point's layer depth comes from (m; inf inside)."""
    x, y, z = points[:, 0], np.abs(points[:, 1]), points[:, 2]
    x_lo, x_hi, y_hi, z_lo = inner
    x0, x1, w, d = outer
    best, out = np.zeros(len(x)), np.full(len(x), math.inf)
    for dist, thick in ((x_lo - x, x_lo - x0), (x - x_hi, x1 - x_hi), (y - y_hi, w - y_hi),
                        (z_lo - z, z_lo - d)):
        if thick <= 0.0:
            continue
        s = np.clip(dist, 0.0, None) / thick
        take = s > best
        best[take], out[take] = s[take], thick
    return out


def inside(params, nodes, point):
    """True when `point` (x, y, z) lies in the absorbing layers (where
    they damp: a record there is not a result)."""
    if params.absorbing is None:
        return False
    xs, ys, zs = nodes
    return bool(profile(np.array([point], dtype=float), params.absorbing,
                        (xs[0], xs[-1], ys[-1], zs[0]))[0] > 0.0)


def peak_damping(c, thick, reflection):
    """a_max (1/s) of a layer `thick` m thick for waves at c m/s: a trip
    through the quadratic profile and back takes exp(-a_max L / (3 c)) =
    `reflection` off them."""
    return 3.0 * c * math.log(1.0 / reflection) / thick


def damping_field(mesh, params, nodes, cs):
    """The cell-wise (DG0) a0 of the layers (1/s); `cs` the cell-wise
    shear-wave speed (layer_fields)."""
    Q = cs.function_space
    a0 = fem.Function(Q, name="a0_layer")
    tdim = mesh.topology.dim
    imap = mesh.topology.index_map(tdim)
    n_cells = imap.size_local + imap.num_ghosts
    mid = dolfinx.mesh.compute_midpoints(mesh, tdim, np.arange(n_cells, dtype=np.int32))
    xs, ys, zs = nodes
    outer = (xs[0], xs[-1], ys[-1], zs[0])
    s = profile(mid, params.absorbing, outer)
    thick = thickness(mid, params.absorbing, outer)
    dofs = Q.dofmap.list.array.reshape(-1)[:n_cells]
    c = cs.x.array[dofs]
    with np.errstate(divide="ignore", invalid="ignore"):
        a_max = np.where(s > 0.0, peak_damping(c, thick, params.absorbing_reflection), 0.0)
    a0.x.array[dofs] = a_max * s**2
    return a0
