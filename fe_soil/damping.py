"""The soil's material damping and absorbing layers as operators: the
diagonal part C = a0 M (+ the absorbing layers' mass-proportional damping
and the boundary's dashpots) and the stiffness-proportional part a1 K,
each layer's damping ratio matched over [soil] damping_band by
params.damping_law (filtered above [soil] damping_cutoff)."""
from __future__ import annotations

import math

import numpy as np
from dolfinx import fem
import dolfinx.fem.petsc  # noqa: F401  (registers fem.petsc)
import dolfinx.mesh

from . import absorbing, forms, ground_shapes, path_measures
from .params import damping_law, rayleigh_coefficients


def _merge_counts(dicts):
    """The sum of {value: count} dicts (one per rank)."""
    return {v: sum(d.get(v, 0) for d in dicts) for v in set().union(*dicts)}


def operators(soil, f, ds, stiffness_over):
    """(c, tau, a1_max, parts) for the soil's space and fields f: the
    diagonal damping per DOF, the filter's time constant (0: none), the
    largest layer's a1, and the step's product K u + a1 K v as parts
    [(a1, A)], one per damping ratio: sum A (u + a1 v). The first is the
    most common ratio's (by cells) with the boundary's springs: its A is
    `stiffness_over(cells)` (cells None: every cell, the whole K), the
    others the elasticity over their cells alone."""
    V, p = soil.V, soil.p
    xi = f["xi"]
    A0, A1 = damping_law(*p.damping_band, p.damping_cutoff)
    tau = 1.0 / (2.0 * math.pi * p.damping_cutoff) if p.damping_cutoff > 0.0 else 0.0
    a0 = fem.Constant(soil.mesh, A0) * xi
    if p.absorbing is not None:
        a0 = a0 + absorbing.damping_field(soil.mesh, p, soil.nodes, f["cs"])
    c = forms.lumped_damping(V, f, ds, a0, p.dashpots)
    xis = {layer.damping for layer in p.layers} | set(path_measures.damping_ratios(p.measures))
    xis |= set(ground_shapes.damping_ratios(p.ground)) if p.ground is not None else set()
    a1_max = rayleigh_coefficients(max(xis), *p.damping_band, p.damping_cutoff)[1]
    # One product per ratio over its own cells: each matrix entry is read
    # once a step. (The earlier split, a1_ref K (u + a1_ref v) over every
    # cell plus the excess (a1 - a1_ref) K v over the other ratios' cells,
    # read those cells twice: on the layered ground-vibration block 37 % of
    # K's entries again; docs/fe-soil.md.)
    n_cells = soil.mesh.topology.index_map(3).size_local
    cell_xi = xi.x.array[xi.function_space.dofmap.list.array.reshape(-1)[:n_cells]]
    values, counts = np.unique(cell_xi, return_counts=True)
    counts = _merge_counts(soil.comm.allgather(
        {float(v): int(n) for v, n in zip(values, counts)}))
    ratios = sorted(counts, key=lambda v: (-counts[v], v))  # the most common first
    if len(ratios) == 1:
        return c, tau, a1_max, [(rayleigh_coefficients(ratios[0], *p.damping_band,
                                                       p.damping_cutoff)[1], None)]
    tag = np.zeros(n_cells, dtype=np.int32)
    for k, r in enumerate(ratios):
        tag[cell_xi == r] = k + 1
    cells = dolfinx.mesh.meshtags(soil.mesh, 3, np.arange(n_cells, dtype=np.int32), tag)
    parts = []
    for k, r in enumerate(ratios):
        a1 = rayleigh_coefficients(r, *p.damping_band, p.damping_cutoff)[1]
        if k == 0:
            A = stiffness_over((cells, 1))
        else:
            A = forms.assembled(forms.damping_stiffness_form(
                V, f, fem.Constant(soil.mesh, 1.0), (cells, k + 1)))
        parts.append((a1, A))
    return c, tau, a1_max, parts
