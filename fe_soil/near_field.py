"""The footprints' near field: the static compliance the block's mesh cannot
hold under a footprint, added at the footprint.

At the mesh-size rule a 0.25 m wide sleeper footprint lies inside one or
two elements of about 0.5 m: the Q1 field cannot bend under its edges and
the footprint's mean displacement is too small (0.82 of the flexible
rectangle's closed form on the homogeneous half-space). Resolving it takes
elements of about 0.06 m along the track and in depth, which the tensor
grid would carry along the whole track and the explicit step could not
afford. But a footprint's near field is quasi-static up to the mesh's
f_max (the shear wavelength at 20 Hz is 6 m or more against the footprint's
0.25 m): what the mesh misses is a static compliance c_loc (m/N: mean
displacement per unit force on that footprint alone), which the soil adds
to each footprint's displacement (FESoil: u_k + c_loc F_k; the velocity is
the FE's, since c_loc dF_k/dt would close a loop of gain d_b c_loc / H with
the ballast's damper in an explicit coupling).

c_loc comes from a local problem at set-up: the footprint alone on a small
block of the scene's layers (its boundary springs as the scene block's),
solved twice, on the scene's own node planes around the footprint (the
coarse solve) and on planes refined under it (REFINED_SIZE at its edges
along the track and at the surface, REFINED_SIZE_EDGE at its long edges,
growing by REFINED_GROWTH to the scene's spacing). c_loc is their
difference: the block
and its springs are in both and cancel to first order; what remains is what
the scene's spacing misses near the footprint. The refined solve does not
depend on where the scene's planes lie, so it is made once per footprint
shape; the coarse one once per pattern of planes around a footprint; both
are cached across runs (cached_compliance).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os

import numpy as np
from mpi4py import MPI

from . import far_field, forms
from .params import Footprint

REACH = 1.5  # m of soil beyond the footprint's edges, and twice that below the surface
REFINED_SIZE = 0.03  # m: the refined solve's elements along the track and in depth
REFINED_SIZE_EDGE = 0.06  # m: across the track, at the footprint's long edges
REFINED_GROWTH = 1.25
SOLVE_RTOL = 1e-7  # the refined block's iterative solve


def rectangle_integral(a, b):
    """The integral of 1/|p - q| over p and q in an a x b rectangle:
    (2/3)(a^3 + b^3 - d^3) + 2 a^2 b ln((b + d)/a) + 2 a b^2 ln((a + d)/b),
    d^2 = a^2 + b^2."""
    d = math.hypot(a, b)
    return ((2.0 / 3.0) * (a**3 + b**3 - d**3) + 2.0 * a * a * b * math.log((b + d) / a)
            + 2.0 * a * b * b * math.log((a + d) / b))


def flexible_rectangle(layer, along, across):
    """The mean vertical displacement per unit force (m/N) of a uniformly
    loaded flexible rectangle on the homogeneous half-space: Boussinesq's
    (1 - nu)/(2 pi G r) integrated over the rectangle and averaged over it."""
    g = layer.shear_modulus
    area = along * across
    return (1.0 - layer.poisson) / (2.0 * math.pi * g) * rectangle_integral(along, across) / area**2


def window(planes, lo, hi, keep=()):
    """The planes strictly inside (lo, hi) with lo and hi added; a plane
    closer to lo or hi than a third of the spacing there is dropped (no
    sliver elements) unless it is in `keep`."""
    planes = np.asarray(planes, dtype=float)
    h = np.diff(planes)
    spacing = lambda v: h[min(max(int(np.searchsorted(planes, v)) - 1, 0), len(h) - 1)]
    kept = lambda v: any(abs(v - k) < 1e-9 for k in keep)
    inside = [float(v) for v in planes if lo < v < hi]
    return [lo] + [v for v in inside if min(v - lo, hi - v) >= spacing(v) / 3.0 or kept(v)] + [hi]


@dataclasses.dataclass
class LocalBlock:
    """The local problem of one footprint, in the footprint's frame (its
    centre at x = 0, and at y = 0 unless it is off the symmetry plane):
    extents and the scene's planes inside them."""

    x: list
    y: list
    z: list
    symmetric: bool
    footprint: Footprint
    interfaces: list  # the layer interfaces among the z planes


def local_block(params, nodes, fp):
    """The footprint's local block on the scene's node planes `nodes`: the
    symmetry plane kept where the scene has one within the block's reach
    of the footprint (the mirror footprint is then loaded too, as in the
    scene)."""
    xs, ys, zs = (np.asarray(a, dtype=float) for a in nodes)
    hx, hy = 0.5 * fp.along + REACH, 0.5 * fp.across + REACH
    sym = bool(params.symmetric and fp.y - hy <= ys[0])
    x_lo, x_hi = max(fp.x - hx, xs[0]), min(fp.x + hx, xs[-1])
    y_lo, y_hi = (ys[0] if sym else max(fp.y - hy, ys[0])), min(fp.y + hy, ys[-1])
    tops = list(np.cumsum([-l.thickness for l in params.layers[:-1]]))
    z_lo = max(-2.0 * REACH, zs[0])
    y0 = 0.0 if sym else fp.y  # the local frame's y origin
    return LocalBlock([v - fp.x for v in window(xs, x_lo, x_hi)],
                      [v - y0 for v in window(ys, y_lo, y_hi)], window(zs, z_lo, 0.0, keep=tops),
                      sym, Footprint(0.0, fp.along, fp.across, fp.y - y0),
                      [t for t in tops if z_lo < t < 0.0])


def refined_planes(coarse, edges, h_fine, h_max, keep=()):
    """Planes from coarse[0] to coarse[-1] spaced h_fine at each of `edges`
    and growing away from them as elements growing by REFINED_GROWTH do
    (the spacing h_fine + (REFINED_GROWTH - 1) d at a distance d), at most
    h_max; the edges and the planes in `keep` among them."""
    a, b = coarse[0], coarse[-1]
    size = lambda v: min([h_max] + [h_fine + (REFINED_GROWTH - 1.0) * abs(v - e) for e in edges])
    fixed = sorted({a, b} | {float(k) for k in list(keep) + list(edges) if a < k < b})
    out = [a]
    for p, q in zip(fixed[:-1], fixed[1:]):
        x = p
        while True:
            step = min(size(x), size(x + size(x)))
            x += step
            if x > q - 0.5 * size(q):
                break
            out.append(x)
        out.append(q)
    return out


def refined_block(block):
    """The local block's planes refined under its footprint: REFINED_SIZE
    at its edges along the track (x) and at the surface, REFINED_SIZE_EDGE
    at its long edges (y), growing by REFINED_GROWTH away from them to the
    coarse planes' largest spacing on each axis."""
    fp = block.footprint
    h_max = [float(np.diff(a).max()) for a in (block.x, block.y, block.z)]
    inside = lambda a, edges: [e for e in edges if a[0] < e < a[-1]]
    ex = inside(block.x, (fp.x - 0.5 * fp.along, fp.x + 0.5 * fp.along))
    ey = inside(block.y, (fp.y - 0.5 * fp.across, fp.y + 0.5 * fp.across))
    xs = refined_planes(block.x, ex, REFINED_SIZE, h_max[0], keep=ex)
    ys = refined_planes(block.y, ey, REFINED_SIZE_EDGE, h_max[1], keep=ey)
    zs = refined_planes(block.z, [0.0], REFINED_SIZE, h_max[2], keep=block.interfaces)
    return LocalBlock(xs, ys, zs, block.symmetric, fp, block.interfaces)


def mean_compliance(params, block, iterative=False):
    """The footprint's mean downward displacement per unit force (m/N) on
    the local block's planes, on this rank alone: a direct solve, or
    (`iterative`, for the refined block) CG with algebraic multigrid and
    the rigid-body modes."""
    p = dataclasses.replace(params, footprints=[block.footprint], symmetric=block.symmetric,
                            length=block.x[-1] - block.x[0], half_width=block.y[-1],
                            depth=-block.z[0], static_reach=0.0, absorbing=None)
    grid = far_field.GridStatics(p, (block.x, block.y, block.z))
    idx, val, area = grid.loads[0]
    share = 0.5 if block.symmetric and abs(block.footprint.y) < 1e-12 else 1.0  # as FESoil's
    b, x = grid.K.createVecs()
    load = np.zeros(len(grid.mask))
    load[idx] += share / area * val
    b.array[:] = load * grid.mask
    ksp = grid.ksp
    if iterative:
        grid.K.setNearNullSpace(forms.rigid_body_modes(b, grid.coords, grid.mask, MPI.COMM_SELF))
        ksp = far_field.cg_gamg(grid.K, MPI.COMM_SELF)
        x.set(0.0)
    far_field.solve(ksp, b, x, SOLVE_RTOL if iterative else 0.0, " of a footprint's local block")
    return float(np.sum(val * x.array[idx]) / area)


def cache_dir():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "railcosim", "fe_soil", "near_field")


def cached_compliance(params, block, iterative=False):
    """mean_compliance(), kept in cache_dir() under a hash of everything that
    enters it (the planes, the footprint, the layers, the springs, the
    solver), so that the next run of a scene reads it back bitwise."""
    fp = block.footprint
    text = json.dumps({
        "planes": [[float(v) for v in a] for a in (block.x, block.y, block.z)],
        "symmetric": bool(block.symmetric),
        "fp": [float(v) for v in (fp.x, fp.y, fp.along, fp.across)],
        "layers": [[float(v) for v in (l.thickness, l.density, l.shear_speed, l.poisson)]
                   for l in params.layers],
        "springs": list(params.spring_alpha), "iterative": iterative, "rtol": SOLVE_RTOL,
        "version": 1}, sort_keys=True)
    path = os.path.join(cache_dir(), hashlib.sha256(text.encode()).hexdigest()[:24] + ".json")
    try:
        with open(path) as f:
            c = float(json.load(f)["compliance"])
        if math.isfinite(c):
            return c
    except (OSError, ValueError, KeyError, TypeError):
        pass  # not there or not a number: solved again, and written anew
    c = mean_compliance(params, block, iterative)
    try:
        os.makedirs(cache_dir(), exist_ok=True)
        tmp = "%s.%d.tmp" % (path, os.getpid())
        with open(tmp, "w") as f:
            json.dump({"compliance": c}, f)
        os.replace(tmp, path)
    except OSError:
        pass  # a cache that cannot be written costs the next run the solve
    return c


def _key(block):
    fp = block.footprint
    return (tuple(np.round(np.concatenate([block.x, block.y, block.z]), 9)), block.symmetric,
            round(fp.x, 9), round(fp.y, 9), fp.along, fp.across, len(block.x), len(block.y))


def compliances(params, nodes, comm=MPI.COMM_WORLD):
    """c_loc of every footprint (m/N, the same array on every rank); zeros
    unless params.footprint_compliance. Each distinct local problem is
    solved once (or read from the cache), the problems dealt out over the
    ranks."""
    n = len(params.footprints)
    if not params.footprint_compliance or n == 0:
        return np.zeros(n)
    blocks = [local_block(params, nodes, fp) for fp in params.footprints]
    coarse = {_key(b): b for b in blocks}
    refined = {}
    for b in blocks:
        r = refined_block(b)
        refined.setdefault(_key(r), r)
    jobs = [(k, b, False) for k, b in coarse.items()] + [(k, r, True) for k, r in refined.items()]
    mine = {(k, it): cached_compliance(params, b, it)
            for j, (k, b, it) in enumerate(jobs) if j % comm.size == comm.rank}
    found = {}
    for part in comm.allgather(mine):
        found.update(part)
    return np.array([found[(_key(refined_block(b)), True)] - found[(_key(b), False)]
                     for b in blocks])
