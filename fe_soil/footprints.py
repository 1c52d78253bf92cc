"""Sleeper footprints on the surface of the tensor-grid block, integrated
exactly: on the surface z = 0 a Q1 shape function is the product of two
1D hat functions of the node planes in x and y, so the integral of a
footprint rectangle's indicator against it is the product of two 1D hat
integrals over the rectangle's overlap with each element."""
from __future__ import annotations

import numpy as np


def hat_integrals(nodes, lo, hi):
    """Integral over [lo, hi] of each 1D hat function of `nodes` (linear
    elements): an array of len(nodes)."""
    nodes = np.asarray(nodes, dtype=float)
    out = np.zeros(len(nodes))
    for e in range(len(nodes) - 1):
        a, b = nodes[e], nodes[e + 1]
        s, t = max(a, lo), min(b, hi)
        if t <= s:
            continue
        h = b - a
        # Integrals of (b - x)/h and (x - a)/h over [s, t].
        out[e] += ((b - s) ** 2 - (b - t) ** 2) / (2.0 * h)
        out[e + 1] += ((t - a) ** 2 - (s - a) ** 2) / (2.0 * h)
    return out


def hat_values(nodes, x):
    """The value at x of each 1D hat function of `nodes` (two nonzero
    entries inside the nodes' span, none outside)."""
    nodes = np.asarray(nodes, dtype=float)
    out = np.zeros(len(nodes))
    if not nodes[0] <= x <= nodes[-1]:
        return out
    e = min(max(int(np.searchsorted(nodes, x, side="right")) - 1, 0), len(nodes) - 2)
    s = (x - nodes[e]) / (nodes[e + 1] - nodes[e])
    out[e], out[e + 1] = 1.0 - s, s
    return out


def surface_node_index(V, nodes, z=None):
    """For each owned DOF block (node) of the vector space V on the node
    plane at z (None: the top one, the surface), its (i, j) in the node
    planes xs, ys; -1 elsewhere."""
    xs, ys, zs = (np.asarray(a, dtype=float) for a in nodes)
    n_owned = V.dofmap.index_map.size_local
    c = V.tabulate_dof_coordinates()[:n_owned]
    tol = 1e-9 * max(xs[-1] - xs[0], ys[-1] - ys[0], zs[-1] - zs[0])
    top = np.abs(c[:, 2] - (zs[-1] if z is None else z)) <= tol
    i = np.clip(np.searchsorted(xs, c[:, 0] - tol), 0, len(xs) - 1)
    j = np.clip(np.searchsorted(ys, c[:, 1] - tol), 0, len(ys) - 1)
    ok = top & (np.abs(xs[i] - c[:, 0]) <= tol) & (np.abs(ys[j] - c[:, 1]) <= tol)
    return np.where(ok, i, -1), np.where(ok, j, -1)


def footprint_vector(fp, nodes, index):
    """(DOF indices, values, modelled area) of a footprint's load vector:
    values = -integral(indicator * N) on the vertical DOFs (positive down),
    area = the footprint's overlap with the modelled surface."""
    xs, ys, _ = nodes
    ix = hat_integrals(xs, fp.x - 0.5 * fp.along, fp.x + 0.5 * fp.along)
    iy = hat_integrals(ys, fp.y - 0.5 * fp.across, fp.y + 0.5 * fp.across)
    area = float(ix.sum() * iy.sum())
    i, j = index
    on = np.flatnonzero(i >= 0)
    values = ix[i[on]] * iy[j[on]]
    keep = values > 0.0
    return 3 * on[keep] + 2, -values[keep], area
