"""The static far field: statics on the block extended by node planes that
grow geometrically outwards (an infinite-element-like graded extension,
statics only), so that the half-space outside the block carries the static
load with its own stiffness instead of the boundary springs.

The springs k = alpha G/R of the viscous-spring boundary (Liu et al. 2006)
are tuned for waves leaving the block; under a static load they are too
soft (on the ground-vibration block a footprint's static displacement at
4 and 8 m was 1.07 and 1.12 of Boussinesq's). The extension reaches
`static_reach` times the block's largest extent beyond it, each element
`STATIC_GROWTH` times the one before; its outer boundary keeps the springs,
whose error there is small at the block. The static displacement of the
block's nodes is taken from the extended solution; the force the outer soil
then exerts on the block's boundary beyond the springs is kept as a
constant load in the dynamics (`FESoil.statics`), so that the static state
is at rest on the block."""
from __future__ import annotations

import dataclasses

import numpy as np
from dolfinx import fem
import dolfinx.fem.petsc  # noqa: F401  (registers fem.petsc)
from petsc4py import PETSc

from . import footprints, forms
from .mesh import SYMMETRY, block_mesh, facet_tags, layer_fields

STATIC_GROWTH = 2.0  # each extension element this many times the one before
# Up to this many DOFs the extended operator is factorised once (MUMPS
# Cholesky) and every static solve is two triangular solves; above, CG +
# GAMG (whose iterations the extension's long thin elements multiply).
DIRECT_DOFS = 60_000


def _grow(nodes, reach):
    """Node planes past the last of `nodes`, each spacing STATIC_GROWTH times
    the one before, until `reach` beyond it."""
    out = list(nodes)
    h, end = out[-1] - out[-2], out[-1] + reach
    while out[-1] < end - 1e-9 * reach:
        h *= STATIC_GROWTH
        out.append(out[-1] + h)
    return out


def extended_nodes(nodes, reach, symmetric):
    """The block's node planes and the extension's: beyond both ends along
    the track, beyond the far side across it (and the near side when the
    whole width is modelled), below the bottom. Returns the planes and the
    number added before the block's first plane on each axis."""
    xs, ys, zs = (list(a) for a in nodes)
    flip = lambda a: [-v for v in a[::-1]]
    ex = flip(_grow(flip(_grow(xs, reach)), reach))
    ey = _grow(ys, reach) if symmetric else flip(_grow(flip(_grow(ys, reach)), reach))
    ez = flip(_grow(flip(zs), reach))
    return (ex, ey, ez), (len(ex) - len(_grow(xs, reach)), len(ey) - len(_grow(ys, reach)),
                          len(ez) - len(zs))


def cg_gamg(K, comm):
    """CG with algebraic multigrid, started from the given vector."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(K)
    ksp.setType("cg")
    ksp.getPC().setType("gamg")
    ksp.setInitialGuessNonzero(True)
    return ksp


def start_from(basis, forces):
    """The combination of kept solutions (forces, solution, ...) whose forces
    fit `forces` best (least squares in the footprint forces, the same on
    every rank): a static solve starts from it. Zero when none are kept."""
    if not basis:
        return 0.0
    F = np.array([b[0] for b in basis]).T
    alpha = np.linalg.lstsq(F, forces, rcond=None)[0]
    return sum(a * b[1] for a, b in zip(alpha, basis))


def solve(ksp, b, x, rtol, what):
    ksp.setTolerances(rtol=rtol, atol=0.0, max_it=5000)
    ksp.solve(b, x)
    if ksp.getConvergedReason() <= 0:
        raise RuntimeError("soil: static solve%s did not converge (%d)"
                           % (what, ksp.getConvergedReason()))


class StaticExtension:
    """The static operator on the extended block and its solver (CG + GAMG
    with the rigid-body modes), and the map of its solution to the block's
    DOFs (by node-plane indices: the block's planes are the extension's)."""

    BASIS = 24  # solutions kept to start the next solve from

    def __init__(self, params, block_nodes, block_coords, comm):
        self.comm = comm
        ext, self.offset = extended_nodes(block_nodes, params.static_reach *
                                          max(params.length, params.half_width, params.depth),
                                          params.symmetric)
        p = dataclasses.replace(params, x_nodes=ext[0], y_nodes=ext[1], z_nodes=ext[2])
        mesh, self.nodes = block_mesh(p, comm)
        V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
        tags = facet_tags(mesh, self.nodes)
        f = layer_fields(mesh, p)
        centre = fem.Constant(mesh, np.array([0.5 * (ext[0][0] + ext[0][-1]), 0.0, 0.0]))
        a_form = forms.stiffness_form(V, f, forms.boundary_measures(mesh, tags), centre,
                                      p.spring_alpha)
        K = fem.petsc.assemble_matrix(a_form)
        K.assemble()
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        mask = np.ones(n_owned)
        rows = np.array([], dtype=np.int32)
        if p.symmetric:
            Vy, _ = V.sub(1).collapse()
            dofs = fem.locate_dofs_topological((V.sub(1), Vy), 2, tags.find(SYMMETRY))[0]
            dofs = dofs[dofs < n_owned]
            mask[dofs] = 0.0
            rows = (dofs + K.getOwnershipRange()[0]).astype(np.int32)
        K.zeroRowsColumns(rows, 1.0)
        coords = np.repeat(V.tabulate_dof_coordinates()[: n_owned // 3], 3, axis=0)
        K.setNearNullSpace(forms.rigid_body_modes(K.createVecs()[0], coords, mask, comm))
        self.K, self.mask = K, mask
        if V.dofmap.index_map.size_global * 3 <= DIRECT_DOFS:
            self.ksp = PETSc.KSP().create(comm)
            self.ksp.setOperators(K)
            self.ksp.setType("preonly")
            self.ksp.getPC().setType("cholesky")
            self.ksp.getPC().setFactorSolverType("mumps")
        else:
            self.ksp = cg_gamg(K, comm)
        index = footprints.surface_node_index(V, self.nodes)
        self.loads = [footprints.footprint_vector(fp, self.nodes, index) for fp in p.footprints]
        self._to_block = self._block_map(coords, block_nodes, block_coords)
        self.basis = []  # (forces, solution) of the last solves

    def _grid_key(self, coords, nodes, offset):
        """Each row's node index (i, j, k) in `nodes`, shifted by `offset`,
        as one integer over the extended grid (-1 where not on a plane)."""
        key = np.zeros(len(coords), dtype=np.int64)
        ok = np.ones(len(coords), dtype=bool)
        for axis in range(3):
            planes = np.asarray(nodes[axis], dtype=float)
            tol = 1e-9 * (planes[-1] - planes[0])
            i = np.clip(np.searchsorted(planes, coords[:, axis] - tol), 0, len(planes) - 1)
            ok &= np.abs(planes[i] - coords[:, axis]) <= tol
            key = key * len(self.nodes[axis]) + i + offset[axis]
        return np.where(ok, key * 3 + np.arange(len(coords)) % 3, -1)

    def _block_map(self, coords, block_nodes, block_coords):
        """For each owned block DOF, where its value sits in the gathered
        extended solution (every rank's owned values, concatenated)."""
        keys = self._grid_key(coords, self.nodes, (0, 0, 0))
        all_keys = np.concatenate(self.comm.allgather(keys))
        order = np.argsort(all_keys)
        mine = self._grid_key(block_coords, block_nodes, self.offset)
        at = order[np.searchsorted(all_keys, mine, sorter=order)]
        if np.any(mine < 0) or np.any(all_keys[at] != mine):
            raise RuntimeError("soil: the static extension misses nodes of the block")
        return at

    def solve(self, forces, shares, areas, rtol):
        """The block's displacement (owned DOFs) under the footprint forces
        (whole sleeper; `shares` the modelled part of each, `areas` the
        modelled footprint areas of the block)."""
        b, x = self.K.createVecs()
        load = np.zeros(len(self.mask))
        for (idx, val, _), f, s, a in zip(self.loads, forces, shares, areas):
            load[idx] += f * s / a * val
        b.array[:] = load * self.mask
        x.array[:] = start_from(self.basis, forces)
        solve(self.ksp, b, x, rtol, " on the extended block")
        self.basis.append((np.array(forces, dtype=float), x.array.copy()))
        del self.basis[: -self.BASIS]
        return np.concatenate(self.comm.allgather(x.array))[self._to_block]
