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


def operators(soil, f, ds):
    """(c, tau, a1_max, a1_ref, Ka1) for the soil's space and fields f:
    the diagonal damping per DOF, the filter's time constant (0: none),
    the largest layer's a1, the a1 folded into the product K (u + a1 v)
    and the matrix of the other layers' excess (None when all agree)."""
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
    # The stiffness-proportional part a1 K: the a1 of the most common
    # damping ratio (by cells) is folded into the product K (u + a1 v)
    # (v filtered, with a cutoff);
    # the other layers' excess, (a1 - a1_ref) K, is a second matrix
    # assembled over their cells only. On a graded block the half-space
    # holds most cells, so the second product covers the top layers'
    # rows only (measured in docs/fe-soil.md).
    n_cells = soil.mesh.topology.index_map(3).size_local
    cell_xi = xi.x.array[xi.function_space.dofmap.list.array.reshape(-1)[:n_cells]]
    values, counts = np.unique(cell_xi, return_counts=True)
    counts = _merge_counts(soil.comm.allgather(
        {float(v): int(n) for v, n in zip(values, counts)}))
    xi_ref = max(sorted(counts), key=lambda v: counts[v])
    a1 = rayleigh_coefficients(xi_ref, *p.damping_band, p.damping_cutoff)[1]
    Ka1 = None  # the excess over a1 K, when the layers' ratios differ
    if len(xis) > 1:
        other = np.flatnonzero(cell_xi != xi_ref).astype(np.int32)
        cells = dolfinx.mesh.meshtags(soil.mesh, 3, other, np.ones(len(other), dtype=np.int32))
        excess = fem.Constant(soil.mesh, A1) * (xi - fem.Constant(soil.mesh, xi_ref))
        c_form = forms.damping_stiffness_form(V, f, excess, cells)
        Ka1 = fem.petsc.create_matrix(c_form, "baij")
        fem.petsc.assemble_matrix(Ka1, c_form)
        Ka1.assemble()
    return c, tau, a1_max, a1, Ka1
