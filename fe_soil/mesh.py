"""The block mesh of the soil: Q1 hexahedra on a tensor grid, layers as
cell-wise material fields, and the boundary facets tagged."""
from __future__ import annotations

import numpy as np
import dolfinx
import dolfinx.mesh
from dolfinx import fem
from mpi4py import MPI

from . import ground_shapes, path_measures
from .params import SoilParams, axis_nodes

SURFACE = 1  # z = 0
ABSORBING = 2  # the sides x = 0, x = L, y = +-W and the bottom z = -D
SYMMETRY = 3  # y = 0 when the half block is modelled


def block_mesh(params: SoilParams, comm=MPI.COMM_WORLD):
    """The hexahedral block with node planes at the axis coordinates of
    `axis_nodes(params)` (uniform at the mesh-size rule unless given)."""
    xs, ys, zs = (np.asarray(a, dtype=float) for a in axis_nodes(params))
    n = [len(xs) - 1, len(ys) - 1, len(zs) - 1]
    mesh = dolfinx.mesh.create_box(
        comm, [np.zeros(3), np.ones(3)], n, dolfinx.mesh.CellType.hexahedron
    )
    x = mesh.geometry.x
    for axis, nodes in enumerate((xs, ys, zs)):
        x[:, axis] = np.interp(x[:, axis], np.linspace(0.0, 1.0, len(nodes)), nodes)
    return mesh, (xs, ys, zs)


def facet_tags(mesh, nodes):
    xs, ys, zs = nodes
    tol = 1e-8 * max(xs[-1] - xs[0], ys[-1] - ys[0], zs[-1] - zs[0])
    fdim = mesh.topology.dim - 1
    groups = {
        SURFACE: lambda p: np.isclose(p[2], zs[-1], atol=tol),
        ABSORBING: lambda p: np.isclose(p[0], xs[0], atol=tol)
        | np.isclose(p[0], xs[-1], atol=tol)
        | np.isclose(p[1], ys[-1], atol=tol)
        | (np.isclose(p[1], ys[0], atol=tol) & (ys[0] < -tol))
        | np.isclose(p[2], zs[0], atol=tol),
        SYMMETRY: lambda p: np.isclose(p[1], ys[0], atol=tol) & (abs(ys[0]) <= tol),
    }
    indices, values = [], []
    for tag, where in groups.items():
        found = dolfinx.mesh.locate_entities_boundary(mesh, fdim, where)
        indices.append(found)
        values.append(np.full(len(found), tag, dtype=np.int32))
    indices = np.concatenate(indices)
    values = np.concatenate(values)
    # A facet on an edge belongs to one face only (facets are never shared).
    order = np.argsort(indices, kind="stable")
    indices, values = indices[order], values[order]
    keep = np.concatenate([[True], indices[1:] != indices[:-1]]) if len(indices) else []
    return dolfinx.mesh.meshtags(mesh, fdim, indices[keep], values[keep])


def layer_fields(mesh, params: SoilParams):
    """Cell-wise (DG0) density, Lame parameters, P and S speeds and the
    layer's damping ratio; a path measure's cells its own (an open
    trench's: no stiffness, no mass)."""
    Q = fem.FunctionSpace(mesh, ("DG", 0))
    tdim = mesh.topology.dim
    n_cells = mesh.topology.index_map(tdim).size_local + mesh.topology.index_map(tdim).num_ghosts
    mid = dolfinx.mesh.compute_midpoints(mesh, tdim, np.arange(n_cells, dtype=np.int32))
    names = ("rho", "mu", "lam", "cp", "cs", "xi")
    fields = {name: fem.Function(Q, name=name) for name in names}
    dofs = Q.dofmap.list.array.reshape(-1)[:n_cells]  # one DOF per cell
    bottoms = np.cumsum([layer.thickness for layer in params.layers[:-1]])
    layer_of = np.searchsorted(bottoms, -mid[:, 2], side="right")
    values = {}
    for name, attr in (("rho", "density"), ("mu", "shear_modulus"), ("lam", "lame_lambda"),
                       ("cp", "p_speed"), ("cs", "shear_speed"), ("xi", "damping")):
        values[name] = np.array([getattr(layer, attr) for layer in params.layers])[layer_of]
    path_measures.assign(values, mid, params.measures)  # trenches and walls (none: no change)
    if params.ground is not None:  # an embankment's cells, the cells outside the ground
        ground_shapes.assign(values, mid, params.ground)
    for name in names:
        fields[name].x.array[dofs] = values[name]
    return fields
