"""The ground's shape under the FE soil: at grade (flat, the default), an
embankment the track runs on, or a cutting it runs in; each uniform along
the track and symmetric about its centre line. numpy and the standard
library only, so that the keys are checked without dolfinx.

    [soil]
    ground = "bank"             # optional: the shape a plain run builds
                                # (default "at_grade": the flat ground)
    [[soil.grounds]]
    name = "bank"               # letters, digits, _ or -
    shape = "embankment"        # "at_grade", "embankment" or "cutting"
    height = 2.0                # m above the ground around it
    crest_width = 6.0           # m, the full width (the track on its centre line)
    slope = 1.5                 # m across per m of height (1:1.5)
    shear_wave_speed = 200.0    # m/s (or young_modulus in Pa; one of the two)
    poisson = 0.3
    density = 1900.0            # kg/m^3
    damping = 0.04              # material damping ratio
    [[soil.grounds]]
    name = "cut"
    shape = "cutting"
    depth = 2.0                 # m below the ground around it
    base_width = 6.0            # m, the full width at its base
    slope = 1.5

How the shape meets the mesh (`refine`): the block's ground z = 0 is the
ground around the shape; an embankment adds node planes from z = 0 up to
its crest z = height (at most the element size of its material apart,
the rule of a path measure's in-fill), a cutting puts a node plane at its
base z = -depth. Across the track there are node planes at the crest's or
base's edge and at the toe or top of the slope, and on the slope one plane
at the slope's y at the middle height of every element row between them:
the slope is a staircase of one step per element row, whose corners lie on
either side of the true slope. Cells outside the shape's cross-section
(tested at the cell's midpoint, `solid`; with those planes no midpoint
lies on a slope) carry neither stiffness nor mass, like an open trench's
(path_measures.assign): their faces toward the soil are free, and the
nodes that touch no soil are held at zero (model.FESoil).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import path_measures
from .params import Layer
from .soil_table import ConfigError, number

SHAPES = ("at_grade", "embankment", "cutting")
AT_GRADE = "at_grade"  # the built-in flat ground's name
SIZE_KEYS = {"embankment": ("height", "crest_width", "slope"),
             "cutting": ("depth", "base_width", "slope"), "at_grade": ()}


@dataclass
class Ground:
    name: str
    shape: str = AT_GRADE
    height: float = 0.0  # embankment
    depth: float = 0.0  # cutting
    width: float = 0.0  # the crest's or the base's full width
    slope: float = 0.0  # across per unit height
    material: Optional[Layer] = None  # the embankment's
    key: str = ""  # the prefix of its keys in messages ("grounds[1].")

    @property
    def edge(self) -> float:
        """The crest's or base's edge (m from the centre line)."""
        return 0.5 * self.width

    @property
    def rise(self) -> float:
        return self.height if self.shape == "embankment" else self.depth

    @property
    def foot(self) -> float:
        """The embankment's toe or the cutting's top edge (m from the centre line)."""
        return self.edge + self.slope * self.rise

    @property
    def surface(self) -> float:
        """z of the ground under the track."""
        return {"embankment": self.height, "cutting": -self.depth}.get(self.shape, 0.0)


def parse_one(table, k):
    where = "grounds[%d]." % (k + 1)
    if not isinstance(table, dict):
        raise ConfigError("[soil] grounds[%d] must be a table ([[soil.grounds]])" % (k + 1))
    shape = table.get("shape")
    if shape not in SHAPES:
        raise ConfigError("[soil] %sshape must be one of %s (got %r)"
                          % (where, ", ".join('"%s"' % s for s in SHAPES), shape))
    allowed = {"name", "shape"} | set(SIZE_KEYS[shape])
    if shape == "embankment":
        allowed |= path_measures.MATERIAL_KEYS
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ConfigError("[soil] %s%s is not a key of a ground of shape %r (its keys: %s)"
                          % (where, unknown[0], shape, ", ".join(sorted(allowed))))
    name = table.get("name")
    if not isinstance(name, str) or not name or not all(c.isalnum() or c in "_-" for c in name):
        raise ConfigError("[soil] %sname must be letters, digits, _ or - (got %r)" % (where, name))
    g = Ground(name=name, shape=shape, key=where)
    if shape == "embankment":
        g.height = number(table, "height", where, lo=0.0)
        g.width = number(table, "crest_width", where, lo=0.0)
        g.material = path_measures._material(table, where, "embankment")
    elif shape == "cutting":
        g.depth = number(table, "depth", where, lo=0.0)
        g.width = number(table, "base_width", where, lo=0.0)
    if shape != AT_GRADE:
        g.slope = number(table, "slope", where, lo=0.0)
    return g


def parse(table):
    """(the grounds of [[soil.grounds]], the selected one: [soil] ground,
    the flat ground by default)."""
    value = table.get("grounds", [])
    if not isinstance(value, list):
        raise ConfigError("[soil] grounds must be a list of tables ([[soil.grounds]])")
    grounds = [parse_one(t, k) for k, t in enumerate(value)]
    names = [g.name for g in grounds]
    for k, n in enumerate(names):
        if n in names[:k] or n == AT_GRADE:
            raise ConfigError("[soil] grounds[%d].name %r repeats %s" % (
                k + 1, n, "the flat ground's name" if n == AT_GRADE else
                "grounds[%d]'s" % (names.index(n) + 1)))
    chosen = table.get("ground", AT_GRADE)
    if chosen != AT_GRADE and chosen not in names:
        raise ConfigError("[soil] ground must be %r or the name of one of [[soil.grounds]] (%s; "
                          "got %r)" % (AT_GRADE, ", ".join(names) or "none given", chosen))
    return grounds, chosen


def find(grounds, name):
    """The ground of that name (AT_GRADE: the flat one)."""
    for g in grounds:
        if g.name == name:
            return g
    return Ground(name=AT_GRADE)


def solid(g, y, z, tol=1e-9):
    """Which points (|y|, z) lie in the ground (arrays): below z = 0 outside
    a cutting, in an embankment's cross-section above it."""
    y, z = np.abs(np.asarray(y, dtype=float)), np.asarray(z, dtype=float)
    if g.shape == "embankment":
        return (z <= tol) | (y <= g.edge + g.slope * (g.height - z) + tol)
    if g.shape == "cutting":
        return (z <= -g.depth + tol) | (y >= g.edge + g.slope * (z + g.depth) - tol)
    return np.ones(np.broadcast(y, z).shape, dtype=bool)


def check(g, cfg, p, footprints):
    """Refuses, naming the key, a shape the block or the FE soil's parts
    cannot hold: beyond the inner region across or in depth, footprints
    off the crest or base, the static far field or the footprints' own
    compliance (both assume a flat ground), a path measure in its reach."""
    if g.shape == AT_GRADE:
        return
    for key, on in (("static_reach", cfg["static_reach"] > 0.0),
                    ("footprint_compliance", cfg["footprint_compliance"])):
        if on:
            raise ConfigError("[soil] %s: the FE soil's %s assumes a flat ground; with the %s of "
                              "[soil] %sname %r set %s" % (
                                  key, "static far field" if key == "static_reach" else
                                  "footprint compliance", g.shape, g.key, g.name,
                                  "static_reach = 0.0" if key == "static_reach" else
                                  "footprint_compliance = false"))
    _, _, y_hi, z_lo = ((0.0, p.length, p.half_width, -p.depth) if p.absorbing is None
                        else p.absorbing)
    zone = "the block" if p.absorbing is None else "the region inside the absorbing layers"
    if g.foot >= y_hi:
        raise ConfigError("[soil] %sslope: the %s reaches %g m from the track; it must end "
                          "inside %s (%g m)" % (g.key, g.shape, g.foot, zone, y_hi))
    if g.shape == "cutting" and -g.depth <= z_lo:
        raise ConfigError("[soil] %sdepth %g m: the cutting must end above the bottom of %s "
                          "(%g m deep)" % (g.key, g.depth, zone, -z_lo))
    reach = max(f.y + 0.5 * f.across for f in footprints)
    if reach > g.edge:
        raise ConfigError("[soil] %s%s %g m: the track's footprints reach %g m from the centre "
                          "line, beyond the %s's edge (%g m)" % (
                              g.key, "crest_width" if g.shape == "embankment" else "base_width",
                              g.width, reach, "crest" if g.shape == "embankment" else "base",
                              g.edge))
    for m in p.measures:
        if m.y_lo < g.foot:
            raise ConfigError("[soil] measures: %r begins %g m from the track, inside the %s "
                              "(it reaches %g m, [soil] %sslope): place it beyond" % (
                                  m.name, m.y_lo, g.shape, g.foot, g.key))


def _slope_planes(zs, g):
    """The y planes of the slope: its ends and the slope's y at the middle
    of each element row between z = 0 (or -depth) and the crest (or 0)."""
    zs = np.asarray(zs)
    if g.shape == "embankment":
        rows = zs[(zs >= -1e-12)]
        mids = 0.5 * (rows[1:] + rows[:-1])
        ys = g.edge + g.slope * (g.height - mids)
    else:
        rows = zs[(zs >= -g.depth - 1e-12) & (zs <= 1e-12)]
        mids = 0.5 * (rows[1:] + rows[:-1])
        ys = g.edge + g.slope * (mids + g.depth)
    return [g.edge, g.foot] + list(ys)


def refine(p, g, h, h_ground, protect_y=(), protect_z=()):
    """p's node planes with the shape's (the module's docstring): h the
    soil's element size, h_ground the embankment material's."""
    from .path_measures import refine_axis
    from .params import uniform_nodes

    if g.shape == AT_GRADE:
        return p
    if g.shape == "embankment":
        p.z_nodes = sorted(set(p.z_nodes) | set(uniform_nodes(0.0, g.height, h_ground)))
        if h_ground < h:
            p.x_nodes = refine_axis(p.x_nodes, p.x_nodes[0], p.x_nodes[-1], h_ground)
            p.y_nodes = refine_axis(p.y_nodes, 0.0, g.edge, h_ground)
    else:
        # refine_axis's last step may land a round-off below the surface
        p.z_nodes = [0.0 if abs(z) < 1e-12 else z
                     for z in refine_axis(p.z_nodes, -g.depth, 0.0, h, protect=protect_z)]
    ys = refine_axis(p.y_nodes, g.edge, g.foot, h, protect=[0.0, *protect_y])
    planes = _slope_planes(p.z_nodes, g)
    p.y_nodes = sorted(set(y for y in ys if not g.edge < y < g.foot) | set(planes))
    return p


def assign(values, mid, g):
    """The cells' material values (path_measures.assign's dict) with the
    embankment's cells given its material and the cells outside the ground
    none; returns the cells outside (a boolean array)."""
    if g.shape == AT_GRADE:
        return np.zeros(len(mid), dtype=bool)
    void = ~solid(g, mid[:, 1], mid[:, 2])
    if g.shape == "embankment":
        mat = g.material
        bank = (mid[:, 2] > 0.0) & ~void
        for name, value in (("rho", mat.density), ("mu", mat.shear_modulus),
                            ("lam", mat.lame_lambda), ("cp", mat.p_speed),
                            ("cs", mat.shear_speed), ("xi", mat.damping)):
            values[name][bank] = value
    for name in ("rho", "mu", "lam", "cp", "cs"):
        values[name][void] = 0.0
    return void


def surface_z(g, nodes, y):
    """z of the meshed ground's surface at y (m from the centre line): the
    top of the highest solid cell in the columns of cells whose y-span holds
    y (on a flat part the shape's own z; on a slope within one step of it)."""
    ys, zs = (np.asarray(a, dtype=float) for a in nodes[1:])
    y = abs(float(y))
    if g.shape == AT_GRADE:
        return 0.0
    tol = 1e-9 * (ys[-1] - ys[0])
    cols = [e for e in range(len(ys) - 1) if ys[e] - tol <= y <= ys[e + 1] + tol]
    zm = 0.5 * (zs[1:] + zs[:-1])
    best = -np.inf
    for e in cols:
        ok = solid(g, np.full(len(zm), 0.5 * (ys[e] + ys[e + 1])), zm)
        best = max(best, float(zs[1:][ok].max()))
    return best


def damping_ratios(g):
    return [] if g.material is None else [g.material.damping]
