"""Measures on the vibration's path in the FE soil: an open trench, an
in-filled trench and a wave-barrier wall beside the track, each a box in
the half block (y >= 0; the symmetry plane y = 0 mirrors it to the other
side of the track). numpy and the standard library only, so that the keys
are checked without dolfinx.

    [soil]
    variant = "deep"            # optional: the measure a plain run builds
                                # ("reference": none; default: all of them)
    [[soil.measures]]
    name = "deep"               # optional (default measure1, measure2 ...)
    kind = "trench"             # "trench" (open), "infilled_trench" or "wall"
    distance = 6.0              # m from the track's centre line to the near face
    depth = 5.0                 # m below the surface
    width = 0.5                 # m across the track
    length = 12.0               # m along the track
    x0 = 15.0                   # optional, m along the rail: the centre (default
                                # [soil] receiver_x, i.e. the receivers' line)
    # in-filled trench and wall: the material, as a layer's
    shear_wave_speed = 50.0     # m/s (or young_modulus in Pa; one of the two)
    poisson = 0.3
    density = 100.0             # kg/m^3
    damping = 0.05              # material damping ratio

The mesh resolves each measure (`refine`): its faces are node planes, so
the cells inside it are exactly those of the box; a wall or an in-fill has
at least two elements across its width, and inside an in-fill softer than
the softest layer the spacing follows the mesh-size rule with its own
Rayleigh speed (h = c_R / (n f_max), params.mesh_size; with [soil]
mesh_size, that size scaled by the in-fill's c_R over the softest layer's).
An open trench's cells carry neither stiffness nor mass (`assign`): its
faces are free, and the nodes inside it, which touch no soil, are held at
zero (model.FESoil), which is the operator of the block with those cells
removed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional, Sequence

from . import soil_table
from .params import Layer, rayleigh_speed
from .soil_table import ConfigError

KINDS = ("trench", "infilled_trench", "wall")
GEOMETRY_KEYS = {"name", "kind", "distance", "depth", "width", "length", "x0"}
MATERIAL_KEYS = {"young_modulus", "shear_wave_speed", "poisson", "density", "damping"}
REFERENCE = "reference"  # the variant without any measure
MIN_SIZE = 0.1  # of the element size: the smallest width, depth or length of a measure
NEIGHBOURS = 3  # intervals beside a measure's face spaced again (refine_axis)
GROWTH = 1.25  # an element beside a measure's face grows by at most this much (refine_axis)


@dataclass
class Measure:
    """A measure in the rail's frame (x0 None: the receivers' line) or,
    once placed (`place`), in the block's: x_lo..x_hi along, y_lo..y_hi
    across, from z_lo = -depth to the surface."""

    name: str
    kind: str
    distance: float
    depth: float
    width: float
    length: float
    x0: Optional[float] = None
    material: Optional[Layer] = None  # None: an open trench (a void)
    x_lo: float = 0.0
    x_hi: float = 0.0

    @property
    def y_lo(self) -> float:
        return self.distance

    @property
    def y_hi(self) -> float:
        return self.distance + self.width

    @property
    def z_lo(self) -> float:
        return -self.depth


def _material(table, where, kind):
    if "young_modulus" in table and "shear_wave_speed" in table:
        raise ConfigError("[soil] %syoung_modulus and shear_wave_speed both given: give one of "
                          "them (the other follows from density and poisson)" % where)
    nu = soil_table.number(table, "poisson", where, lo=0.0, hi=0.5, lo_open=False)
    rho = soil_table.number(table, "density", where, lo=0.0)
    if "young_modulus" in table:
        e = soil_table.number(table, "young_modulus", where, lo=0.0)
        cs = math.sqrt(e / (2.0 * (1.0 + nu)) / rho)
    elif "shear_wave_speed" in table:
        cs = soil_table.number(table, "shear_wave_speed", where, lo=0.0)
    else:
        raise ConfigError("[soil] %sshear_wave_speed is missing: a %s needs its material "
                          "(shear_wave_speed or young_modulus, poisson, density, damping)"
                          % (where, kind))
    xi = soil_table.number(table, "damping", where, lo=0.0, hi=1.0, lo_open=False, default=0.0)
    return Layer(thickness=0.0, density=rho, shear_speed=cs, poisson=nu, damping=xi)


def parse_one(table, k):
    """Measure k (0-based) of [[soil.measures]], checked key by key."""
    where = "measures[%d]." % (k + 1)
    if not isinstance(table, dict):
        raise ConfigError("[soil] measures[%d] must be a table ([[soil.measures]])" % (k + 1))
    kind = table.get("kind")
    if kind not in KINDS:
        raise ConfigError("[soil] %skind must be one of %s (got %r)"
                          % (where, ", ".join('"%s"' % s for s in KINDS), kind))
    allowed = GEOMETRY_KEYS | (MATERIAL_KEYS if kind != "trench" else set())
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ConfigError("[soil] %s%s is not a key of a%s %s (its keys: %s)"
                          % (where, unknown[0], "n" if kind[0] in "aeiou" else "", kind,
                             ", ".join(sorted(allowed))))
    name = table.get("name", "measure%d" % (k + 1))
    if not isinstance(name, str) or not name or name == REFERENCE or not all(
            c.isalnum() or c in "_-" for c in name):
        raise ConfigError("[soil] %sname must be letters, digits, _ or - and not %r (got %r)"
                          % (where, REFERENCE, name))
    sizes = {key: soil_table.number(table, key, where, lo=0.0)
             for key in ("distance", "depth", "width", "length")}
    x0 = soil_table.number(table, "x0", where) if "x0" in table else None
    material = None if kind == "trench" else _material(table, where, kind)
    return Measure(name=name, kind=kind, x0=x0, material=material, **sizes)


def parse(table):
    """(the measures of [[soil.measures]], the [soil] variant: None for all
    of them, REFERENCE for none, or a measure's name)."""
    value = table.get("measures", [])
    if not isinstance(value, list):
        raise ConfigError("[soil] measures must be a list of tables ([[soil.measures]])")
    measures = [parse_one(t, k) for k, t in enumerate(value)]
    names = [m.name for m in measures]
    for k, n in enumerate(names):
        if n in names[:k]:
            raise ConfigError("[soil] measures[%d].name %r repeats measures[%d]'s"
                              % (k + 1, n, names.index(n) + 1))
    variant = table.get("variant")
    if variant is not None and variant != REFERENCE and variant not in names:
        raise ConfigError("[soil] variant must be %r or the name of one of [[soil.measures]] (%s; "
                          "got %r)" % (REFERENCE, ", ".join(names) or "none given", variant))
    return measures, variant


def selected(measures, variant):
    """The measures a block of that variant holds."""
    if variant is None:
        return list(measures)
    return [] if variant == REFERENCE else [m for m in measures if m.name == variant]


def _key(m, measures, key):
    return "[soil] measures[%d].%s" % ([a.name for a in measures].index(m.name) + 1, key)


def place(measures, all_measures, rx, shift, p, footprints, h=None):
    """The measures in the block's frame (x shifted by `shift`, centred on
    x0 or the receivers' line rx), checked against the block: inside it
    and outside its absorbing layers, clear of the track's footprints and
    of every receiver, none of its sizes below MIN_SIZE of the element size
    h (if given). `all_measures` numbers the keys in messages."""
    out = []
    for m in measures:
        for key in ("width", "depth", "length"):
            if h is not None and getattr(m, key) < MIN_SIZE * h:
                raise ConfigError("%s %g m is below %g of the element size (%g m): the mesh "
                                  "cannot hold it without elements that small, which would "
                                  "shorten the explicit step as much" % (
                                      _key(m, all_measures, key), getattr(m, key), MIN_SIZE, h))
        xc = (rx if m.x0 is None else m.x0) - shift
        q = Measure(**{**m.__dict__, "x_lo": xc - 0.5 * m.length, "x_hi": xc + 0.5 * m.length})
        x_lo, x_hi, y_hi, z_lo = ((0.0, p.length, p.half_width, -p.depth) if p.absorbing is None
                                  else p.absorbing)
        zone = "the block" if p.absorbing is None else "the region inside the absorbing layers"
        for key, bad, limit in (("x0", q.x_lo <= x_lo or q.x_hi >= x_hi,
                                 "%g to %g m along the rail" % (x_lo + shift, x_hi + shift)),
                                ("distance", q.y_hi >= y_hi, "%g m from the track" % y_hi),
                                ("depth", q.z_lo <= z_lo, "%g m deep" % -z_lo)):
            if bad:
                raise ConfigError("%s: the %s (%g to %g m along the rail, %g to %g m from the "
                                  "track, %g m deep) must lie inside %s (%s)"
                                  % (_key(m, all_measures, key), m.kind, q.x_lo + shift,
                                     q.x_hi + shift, q.y_lo, q.y_hi, m.depth, zone, limit))
        for f in footprints:
            if (f.x + 0.5 * f.along > q.x_lo and f.x - 0.5 * f.along < q.x_hi
                    and f.y + 0.5 * f.across > q.y_lo):
                raise ConfigError("%s %g m: the %s overlaps the track's footprints (they reach "
                                  "%g m from the track): place it farther out"
                                  % (_key(m, all_measures, "distance"), m.distance, m.kind,
                                     f.y + 0.5 * f.across))
        for x, y in p.receivers:
            if q.x_lo <= x <= q.x_hi and q.y_lo <= y <= q.y_hi:
                raise ConfigError("%s: the %s (%g to %g m from the track) holds the receiver at "
                                  "%g m: move the measure or the receiver"
                                  % (_key(m, all_measures, "distance"), m.kind, q.y_lo, q.y_hi, y))
        for o in out:
            if (q.x_lo < o.x_hi and o.x_lo < q.x_hi and q.y_lo < o.y_hi and o.y_lo < q.y_hi):
                raise ConfigError("%s: the %s overlaps %r (%s): measures may touch, not overlap"
                                  % (_key(m, all_measures, "distance"), m.kind, o.name,
                                     _key(o, all_measures, "distance")[7:]))
        out.append(q)
    return out


def _respace(xs, a, b, n):
    """xs with the nodes strictly between a and b replaced by n equal steps."""
    kept = [x for x in xs if not a < x < b]
    return sorted(set(kept) | {a + (b - a) * i / n for i in range(1, n)})


def refine_axis(nodes, lo, hi, h_in, protect=()):
    """Node coordinates with planes at lo and hi and at most h_in apart
    between them; on each side the NEIGHBOURS intervals beside the face
    (back to the nearest end or `protect`ed plane, if closer) are spaced
    again evenly at about their mean, so that an element beside a face is
    between 5/6 and GROWTH times its neighbours' size (the smallest sets the
    explicit step)."""
    xs = sorted(float(x) for x in nodes)
    fixed = set(xs[:1] + xs[-1:]) | {float(x) for x in protect} | {lo, hi}
    below = [x for x in xs if x < lo]
    above = [x for x in xs if x > hi]
    out = sorted(set(x for x in xs if not lo <= x <= hi or x in fixed) | {lo, hi})
    for side, face in ((below, lo), (above, hi)):
        if not side:
            continue
        reach = side[-NEIGHBOURS:] if face == lo else side[:NEIGHBOURS]
        anchor = reach[0] if face == lo else reach[-1]
        stops = [x for x in fixed if min(anchor, face) < x < max(anchor, face)]
        if stops:
            anchor = max(stops) if face == lo else min(stops)
        inside = [x for x in xs if min(anchor, face) <= x <= max(anchor, face)] + [face]
        mean = abs(face - anchor) / max(1, len(set(inside)) - 1)
        n = max(1, round(abs(face - anchor) / mean))
        out = _respace(out, min(anchor, face), max(anchor, face), n)
    # Planes closer than round-off are one (a face at the surface z = 0 and
    # the block's top at -2e-16 would give elements of no thickness, and an
    # explicit step of none): the face's exact value is kept.
    tol = 1e-9 * max(1.0, out[-1] - out[0])
    res = [out[0]]
    for a, b in zip(out, out[1:]):
        n = max(1, math.ceil((b - a) / h_in - 1e-9)) if lo - 1e-12 <= a and b <= hi + 1e-12 else 1
        for x in (a + (b - a) * i / n for i in range(1, n + 1)):
            if x - res[-1] > tol:
                res.append(x)
            elif x in (lo, hi):
                res[-1] = x
    return res


def element_size(m, h_soil, c_soil, f_max, n):
    """The largest element inside the measure: the soil's h, below it in an
    in-fill softer than the softest layer (the mesh-size rule at its own
    Rayleigh speed, c_R / (n f_max), or h_soil c_R / c_R,soil with a given
    mesh_size: f_max and n None)."""
    if m.material is None:
        return h_soil
    c = rayleigh_speed(m.material.shear_speed, m.material.poisson)
    if f_max is None:
        return min(h_soil, h_soil * c / c_soil)
    return min(h_soil, c / (n * f_max))


def refine(p, measures, h_soil, c_soil, f_max=None, n=None, protect_z=()):
    """p's node planes (x_nodes, y_nodes, z_nodes) refined so that the mesh
    resolves each measure (the module's docstring)."""
    faces = ([q.x_lo for q in measures] + [q.x_hi for q in measures],
             [q.y_lo for q in measures] + [q.y_hi for q in measures],
             [q.z_lo for q in measures] + list(protect_z))
    # the coarsest first: where two measures share planes the finer spacing wins
    for m in sorted(measures, key=lambda q: -element_size(q, h_soil, c_soil, f_max, n)):
        h = element_size(m, h_soil, c_soil, f_max, n)
        across = h if m.material is None else min(h, 0.5 * m.width)
        p.x_nodes = refine_axis(p.x_nodes, m.x_lo, m.x_hi, h, protect=faces[0])
        p.y_nodes = refine_axis(p.y_nodes, m.y_lo, m.y_hi, across, protect=faces[1])
        p.z_nodes = refine_axis(p.z_nodes, m.z_lo, 0.0, h, protect=faces[2])
    return p


def inside(m, mid, tol=1e-9):
    """Which of the points mid[k] = (x, y, z) lie in the measure's box (|y|:
    the half block's mirror)."""
    x, y, z = mid[:, 0], abs(mid[:, 1]), mid[:, 2]
    return ((x > m.x_lo + tol) & (x < m.x_hi - tol) & (y > m.y_lo + tol) & (y < m.y_hi - tol)
            & (z > m.z_lo + tol))


def assign(values, mid, measures):
    """The cell-wise material values (a dict of arrays, one entry a cell:
    rho, mu, lam, cp, cs, xi) with each measure's cells given its material,
    an open trench's zero stiffness and mass (its damping ratio kept);
    returns the cells of any measure (a boolean array)."""
    import numpy as np

    any_cell = np.zeros(len(mid), dtype=bool)
    for m in measures:
        cells = inside(m, mid)
        any_cell |= cells
        mat = m.material
        new = ({"rho": 0.0, "mu": 0.0, "lam": 0.0, "cp": 0.0, "cs": 0.0} if mat is None else
               {"rho": mat.density, "mu": mat.shear_modulus, "lam": mat.lame_lambda,
                "cp": mat.p_speed, "cs": mat.shear_speed, "xi": mat.damping})
        for name, value in new.items():
            values[name][cells] = value
    return any_cell


def damping_ratios(measures: Sequence[Measure]) -> List[float]:
    """The material damping ratios the measures bring into the block."""
    return [m.material.damping for m in measures if m.material is not None]
