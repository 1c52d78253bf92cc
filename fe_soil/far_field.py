"""The static far field: the correction the half-space outside the block
makes to the block's statics, from a coarse copy of the block and its graded
extension.

The springs k = alpha G/R of the viscous-spring boundary (Liu et al. 2006)
are tuned for waves leaving the block; under a static load they are too
soft (on the ground-vibration block a footprint's static displacement at
4 and 8 m was 1.07 and 1.12 of Boussinesq's). Statics on the block extended
by node planes growing geometrically outwards (an infinite-element-like
graded extension, statics only) carry the load with the outer soil's own
stiffness, but the block's fine node planes run through the extension on
a tensor grid: twice the DOFs, elements of aspect ratios in the hundreds,
and a solve ten times the block's.

So the extension is solved on a coarse grid only, for the difference it
makes: the block's node planes thinned to about COARSE_ELEMENTS elements
along its largest extent (a subset of them, keeping the layer interfaces),
that coarse block solved once with its springs and once extended by
`static_reach` times its largest extent, each extension element
STATIC_GROWTH times the one before, its outer boundary keeping the springs.
The difference of the two on the block is what the outer soil changes;
near the load the two coarse solutions share their mesh and its error, so
it is smooth, and its trilinear interpolation is added to the fine block's
own static solution (`FESoil.statics`). Both coarse operators are small:
rank 0 factorises them once (MUMPS Cholesky, on its own) and sends the
difference to the other ranks; each later static solve adds two pairs of
triangular solves. The force the outer soil
then exerts on the block beyond its springs is held as a constant load in
the dynamics, so the static state is at rest on the block."""
from __future__ import annotations

import dataclasses

import numpy as np
from dolfinx import fem
import dolfinx.fem.petsc  # noqa: F401  (registers fem.petsc)
from mpi4py import MPI
from petsc4py import PETSc

from . import footprints, forms
from .mesh import SYMMETRY, block_mesh, facet_tags, layer_fields

STATIC_GROWTH = 2.0  # each extension element this many times the one before
COARSE_ELEMENTS = 12  # the coarse block's elements along its largest extent


def _grow(nodes, reach, h):
    """Node planes past the last of `nodes`, the first spacing STATIC_GROWTH
    times h (or the last spacing, if larger), each next one STATIC_GROWTH
    times the one before, until `reach` beyond it."""
    out = list(nodes)
    h, end = max(h, out[-1] - out[-2]), out[-1] + reach
    while out[-1] < end - 1e-9 * reach:
        h *= STATIC_GROWTH
        out.append(out[-1] + h)
    return out


def extended_nodes(nodes, reach, symmetric, h=0.0):
    """The block's node planes and the extension's (its first element
    STATIC_GROWTH times h at least): beyond both ends along the track,
    beyond the far side across it (and the near side when the whole width
    is modelled), below the bottom. Returns the planes and the number added
    before the block's first plane on each axis."""
    xs, ys, zs = (list(a) for a in nodes)
    flip = lambda a: [-v for v in a[::-1]]
    both = lambda a: flip(_grow(flip(_grow(a, reach, h)), reach, h))
    ex = both(xs)
    ey = _grow(ys, reach, h) if symmetric else both(ys)
    ez = flip(_grow(flip(zs), reach, h))
    return (ex, ey, ez), (len(ex) - len(_grow(xs, reach, h)), len(ey) - len(_grow(ys, reach, h)),
                          len(ez) - len(zs))


def coarse_planes(planes, h, keep=()):
    """A subset of `planes` spaced about h apart: the first and the last, the
    ones in `keep` (layer interfaces), and a plane wherever the last one
    kept lies h or more behind it; a last gap under h/2 is closed by
    dropping the plane before it (unless kept)."""
    planes = [float(v) for v in planes]
    tol = 1e-9 * (planes[-1] - planes[0])
    must = lambda v: any(abs(v - k) <= tol for k in keep)
    out = [planes[0]]
    for v in planes[1:-1]:
        if must(v) or v - out[-1] >= h - tol:
            out.append(v)
    if len(out) > 1 and planes[-1] - out[-1] < 0.5 * h and not must(out[-1]):
        out.pop()
    return out + [planes[-1]]


def coarse_size(nodes):
    """The coarse block's element size: its largest extent over
    COARSE_ELEMENTS."""
    return max(a[-1] - a[0] for a in nodes) / COARSE_ELEMENTS


def coarse_nodes(params, nodes):
    """The coarse block's node planes: every axis thinned to elements of
    about coarse_size (where the block's are finer), the z planes of the
    layer interfaces kept."""
    h = coarse_size(nodes)
    tops = -np.cumsum([layer.thickness for layer in params.layers[:-1]])
    return (coarse_planes(nodes[0], h), coarse_planes(nodes[1], h),
            coarse_planes(nodes[2], h, keep=list(tops)))


def cg_gamg(K, comm, counter=None):
    """CG with algebraic multigrid, started from the given vector. With a
    `counter`, a monitor adds each iteration to its static_iterations: the
    progress the participant shows while a long static solve runs (the
    monitor, Python code, also lets the SDK's progress thread take the GIL
    between iterations)."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(K)
    ksp.setType("cg")
    ksp.getPC().setType("gamg")
    ksp.setInitialGuessNonzero(True)
    if counter is not None:
        def monitor(_ksp, _iteration, _residual):
            counter.static_iterations = getattr(counter, "static_iterations", 0) + 1
        ksp.setMonitor(monitor)
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


def forcing(forces, last, rtol, eta=1e-2, cap=1e-4):
    """An iterated static solve's residual: `eta` times the forces' relative
    change since the `last` solve, at most `cap`, at least `rtol` (the same
    on every rank, as the forces are)."""
    change = np.linalg.norm(forces - last) / max(np.linalg.norm(forces), 1e-300)
    return min(cap, max(rtol, eta * change))


def solve(ksp, b, x, rtol, what):
    ksp.setTolerances(rtol=rtol, atol=0.0, max_it=5000)
    ksp.solve(b, x)
    if ksp.getConvergedReason() <= 0:
        raise RuntimeError("soil: static solve%s did not converge (%d)"
                           % (what, ksp.getConvergedReason()))


def trilinear(nodes, points):
    """The Q1 interpolation on a tensor grid at `points` (n x 3): for each
    point the flat indices (n x 8) of the grid nodes around it (index i, j, k
    of the planes as (i ny + j) nz + k) and their weights (n x 8)."""
    cells, fracs = [], []
    for axis, planes in enumerate(nodes):
        planes = np.asarray(planes, dtype=float)
        e = np.clip(np.searchsorted(planes, points[:, axis], side="right") - 1, 0, len(planes) - 2)
        s = np.clip((points[:, axis] - planes[e]) / (planes[e + 1] - planes[e]), 0.0, 1.0)
        cells.append(e)
        fracs.append(s)
    ny, nz = len(nodes[1]), len(nodes[2])
    index, weight = [], []
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                index.append(((cells[0] + a) * ny + cells[1] + b) * nz + cells[2] + c)
                weight.append(np.where(a, fracs[0], 1.0 - fracs[0]) *
                              np.where(b, fracs[1], 1.0 - fracs[1]) *
                              np.where(c, fracs[2], 1.0 - fracs[2]))
    return np.array(index).T, np.array(weight).T


class GridStatics:
    """The static operator of the block on the node planes `nodes` (springs
    on its absorbing faces, u_y = 0 on a symmetry plane), on this rank alone,
    factorised once; its solutions as arrays over the grid (nx, ny, nz, 3)."""

    def __init__(self, params, nodes):
        p = dataclasses.replace(params, x_nodes=nodes[0], y_nodes=nodes[1], z_nodes=nodes[2])
        mesh, self.nodes = block_mesh(p, MPI.COMM_SELF)
        V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
        tags = facet_tags(mesh, self.nodes)
        centre = fem.Constant(mesh, np.array([0.5 * (nodes[0][0] + nodes[0][-1]), 0.0, 0.0]))
        a_form = forms.stiffness_form(V, layer_fields(mesh, p), forms.boundary_measures(mesh, tags),
                                      centre, p.spring_alpha)
        self.K = fem.petsc.assemble_matrix(a_form)
        self.K.assemble()
        self.mask = np.ones(V.dofmap.index_map.size_local * 3)
        if p.symmetric:
            Vy, _ = V.sub(1).collapse()
            dofs = fem.locate_dofs_topological((V.sub(1), Vy), 2, tags.find(SYMMETRY))[0]
            self.mask[dofs] = 0.0
            self.K.zeroRowsColumns(dofs.astype(np.int32), 1.0)
        self.ksp = PETSc.KSP().create(MPI.COMM_SELF)
        self.ksp.setOperators(self.K)
        self.ksp.setType("preonly")
        self.ksp.getPC().setType("cholesky")
        self.ksp.getPC().setFactorSolverType("mumps")
        index = footprints.surface_node_index(V, self.nodes)
        self.loads = [footprints.footprint_vector(fp, self.nodes, index) for fp in p.footprints]
        # Each node's place in the grid (the planes are the grid's, exactly).
        c = V.tabulate_dof_coordinates()[: V.dofmap.index_map.size_local]
        self.coords = np.repeat(c, 3, axis=0)  # one row per DOF
        ijk = [np.searchsorted(np.asarray(a), c[:, k] - 1e-9 * (a[-1] - a[0]))
               for k, a in enumerate(self.nodes)]
        self.shape = tuple(len(a) for a in self.nodes)
        self.order = np.argsort(np.ravel_multi_index(ijk, self.shape))

    def solve(self, forces, shares):
        """The displacement under the footprint forces (whole sleeper,
        `shares` the modelled part of each) as an array (nx, ny, nz, 3)."""
        b, x = self.K.createVecs()
        load = np.zeros(len(self.mask))
        for (idx, val, area), f, s in zip(self.loads, forces, shares):
            if area > 0.0:
                load[idx] += f * s / area * val
        b.array[:] = load * self.mask
        solve(self.ksp, b, x, 0.0, " of the coarse block")
        return x.array.reshape(-1, 3)[self.order].reshape(self.shape + (3,))


class StaticExtension:
    """The far-field correction of the block's statics: the coarse block
    extended minus the coarse block alone, interpolated to the block's
    owned DOFs (`dof_coords`, one row per DOF, components in turn). Rank 0
    of `comm` holds and solves the coarse operators and sends the
    difference on the coarse grid to every rank (a few thousand numbers)."""

    def __init__(self, params, block_nodes, dof_coords, comm):
        self.comm = comm
        coarse = coarse_nodes(params, block_nodes)
        reach = params.static_reach * max(params.length, params.half_width, params.depth)
        ext, self.offset = extended_nodes(coarse, reach, params.symmetric, coarse_size(block_nodes))
        self.block = self.extended = None
        if comm.rank == 0:
            self.block = GridStatics(params, coarse)
            self.extended = GridStatics(params, ext)
        self.index, self.weight = trilinear(coarse, dof_coords)
        self.component = np.arange(len(dof_coords)) % 3

    def dofs(self):
        """The coarse operators' sizes: (block, extended), on every rank."""
        sizes = (self.block.K.getSize()[0], self.extended.K.getSize()[0]) if self.block else None
        return self.comm.bcast(sizes, root=0)

    def correction(self, forces, shares):
        """What the outer soil adds to the block's static displacement under
        the footprint forces, at the block's owned DOFs."""
        diff = None
        if self.block is not None:
            u_block = self.block.solve(forces, shares)
            u_ext = self.extended.solve(forces, shares)
            (i, j, k), (nx, ny, nz) = self.offset, u_block.shape[:3]
            diff = (u_ext[i : i + nx, j : j + ny, k : k + nz] - u_block).reshape(-1, 3)
        diff = self.comm.bcast(diff, root=0)
        return np.sum(self.weight * diff[self.index, self.component[:, None]], axis=1)
