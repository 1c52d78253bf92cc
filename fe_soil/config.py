"""The FE soil participant's own configuration: the scene's [soil] table
(model = "fe"), checked key by key, and the block it describes around the
footprints the master sends. numpy and the standard library only, so that
the checks run without dolfinx.

    [soil]
    model = "fe"
    ranks = 1                    # MPI ranks the master starts it on
    f_max = 20.0                 # Hz, highest frequency of interest (mesh-size rule)
    elements_per_wavelength = 12.0
    mesh_size = 0.5              # optional, m: overrides the rule
    depth = 20.0                 # m
    margin = 8.0                 # m beyond the track's ends and the farthest receiver
    margin_along = 12.0          # optional, m beyond the track's ends (default: margin)
    growth = 1.0                 # > 1: a graded mesh (the rule only where needed), see below
    resolve_to = 16.0            # m from the track axis: the graded mesh's fine zone across
    static_reach = 5.0           # statics on the block extended this many times its size (0: off)
    footprint_compliance = true  # the static compliance the mesh misses under each footprint,
                                 # added to its outputs (fe_soil/near_field.py; false: the FE alone)
    fine_depth = 9.2             # m: the graded mesh keeps the rule's spacing to here (default
                                 # the softest layer's Rayleigh wavelength at f_max / 2)
    absorbing_reflection = 0.01  # the graded zones' absorbing layers: their nominal reflection
                                 # (0 < R <= 1; 1: no layers), fe_soil/absorbing.py
    receivers = [4.0, 8.0, 16.0, 32.0]   # m from the track axis
    receiver_x = 15.0            # optional, m along the rail (default: its middle)
    damping_band = [5.0, 50.0]   # Hz, the damping fit: each layer's ratio matched at both
    damping_cutoff = 100.0       # Hz, >= the band's top: the stiffness-proportional part acts on
                                 # the velocity filtered above it (0: Rayleigh damping as before)
    variant = "reference"        # optional: which [[soil.measures]] a run builds
                                 # (fe_soil/path_measures.py; default all of them)
    [soil.mitigation]            # optional: the insertion-loss study's load (fe_soil/mitigation.py)
    [[soil.measures]]            # optional: trenches and walls (fe_soil/path_measures.py)
    ground = "at_grade"          # optional: which [[soil.grounds]] a run builds
    [[soil.grounds]]             # optional: embankments and cuttings (fe_soil/ground_shapes.py)
    [[soil.layers]]              # top down; the last reaches the bottom
    thickness = 2.0              # m
    density = 1800.0             # kg/m^3
    shear_wave_speed = 150.0     # m/s
    poisson = 0.33
    damping = 0.03               # material damping ratio
"""
from __future__ import annotations

import math
import os

from . import ground_shapes, path_measures, soil_table
from .params import (Footprint, SoilParams, graded_nodes, rayleigh_speed,
                     uniform_nodes)
from .soil_table import ConfigError


TOP_KEYS = {"model", "ranks", "f_max", "elements_per_wavelength", "mesh_size", "depth", "margin",
            "receivers", "receiver_x", "damping_band", "layers", "growth", "resolve_to",
            "static_reach", "absorbing_reflection", "fine_depth", "margin_along",
            "footprint_compliance", "damping_cutoff", "measures", "variant",
            "mitigation", "grounds", "ground"}
DEFAULTS = {"ranks": 1, "f_max": 20.0, "elements_per_wavelength": 12.0, "depth": 20.0,
            "margin": 8.0, "receivers": [4.0, 8.0, 16.0, 32.0], "damping_band": [5.0, 50.0],
            "static_reach": 5.0, "absorbing_reflection": 0.01,
            "damping_cutoff": 100.0}
MAX_RANKS = 256
# What one configuration may ask of the machine, derived from its keys before
# anything is meshed. Memory: measured on one rank (scenes/ground_vibration_ci
# .toml at mesh_size 1.0, 0.5 and 0.35 m: 6,216, 39,312 and 110,466 DOFs in
# 118, 224 and 463 MiB peak) as about 3.4 KiB a DOF over a base of about
# 100 MiB; the bound counts 4 KiB a DOF over 128 MiB.
MAX_DOFS = 2_000_000
MAX_AXIS_ELEMENTS = 4096     # along one axis: a list of node planes, not yet a mesh
BYTES_PER_DOF = 4096
BASE_BYTES = 128 << 20


def ranks_of(table):
    """The number of MPI ranks the table asks for (an int >= 1)."""
    r = table.get("ranks", 1)
    if isinstance(r, bool) or not isinstance(r, int) or not 1 <= r <= MAX_RANKS:
        raise ConfigError("[soil] ranks must be a whole number from 1 to %d (got %r)"
                          % (MAX_RANKS, r))
    ram = memory_bytes()
    if ram and r * BASE_BYTES > ram // 2:
        raise ConfigError("[soil] ranks = %d starts %d processes of at least %d MiB each (%.1f GiB "
                          "before any mesh); this machine holds %d (half its %.1f GiB): use fewer "
                          "ranks" % (r, r, BASE_BYTES >> 20, r * BASE_BYTES / 2**30,
                                     max(1, ram // 2 // BASE_BYTES), ram / 2**30))
    return r


def parse(table):
    """The checked settings of a [soil] table, as a dict of plain values."""
    unknown = sorted(set(table) - TOP_KEYS)
    if unknown:
        raise ConfigError("[soil] %s is not a key of the FE soil (its keys: %s)"
                          % (unknown[0], ", ".join(sorted(TOP_KEYS))))
    if table.get("model", "fe") != "fe":
        raise ConfigError("[soil] model is %r; this program is the FE soil (model = \"fe\")"
                          % table.get("model"))
    out = {"ranks": ranks_of(table)}
    for key in ("f_max", "elements_per_wavelength", "depth", "margin"):
        out[key] = soil_table.number(table, key, "", lo=0.0, default=DEFAULTS[key])
    out["margin_along"] = (soil_table.number(table, "margin_along", "", lo=0.0)
                           if "margin_along" in table else out["margin"])
    out["mesh_size"] = soil_table.number(table, "mesh_size", "", lo=0.0) if "mesh_size" in table else None
    out["static_reach"] = soil_table.number(table, "static_reach", "", lo=0.0, hi=100.0,
                                            lo_open=False, default=DEFAULTS["static_reach"])
    out["footprint_compliance"] = table.get("footprint_compliance", True)
    if not isinstance(out["footprint_compliance"], bool):
        raise ConfigError("[soil] footprint_compliance must be true or false (got %r)"
                          % (out["footprint_compliance"],))
    out["absorbing_reflection"] = soil_table.number(
        table, "absorbing_reflection", "", lo=0.0, default=DEFAULTS["absorbing_reflection"])
    if out["absorbing_reflection"] > 1.0:
        raise ConfigError("[soil] absorbing_reflection must be <= 1 (1: no absorbing layers; got %g)"
                          % out["absorbing_reflection"])
    out["fine_depth"] = (soil_table.number(table, "fine_depth", "", lo=0.0, lo_open=False)
                         if "fine_depth" in table else None)
    out["growth"] = soil_table.number(table, "growth", "", lo=1.0, hi=2.0, lo_open=False, default=1.0)
    if out["growth"] > 1.0 and out["mesh_size"] is not None:
        raise ConfigError("[soil] growth %g grades the mesh of the f_max rule; it cannot be combined "
                          "with mesh_size (remove one of them)" % out["growth"])
    out["receivers"] = soil_table.receivers(table, DEFAULTS["receivers"])
    out["receiver_x"] = soil_table.optional_number(table, "receiver_x")
    band = soil_table.numbers(table, "damping_band", DEFAULTS["damping_band"], 2)
    if not 0.0 < band[0] < band[1]:
        raise ConfigError("[soil] damping_band must be two frequencies 0 < f1 < f2 (got %r)" % band)
    out["damping_band"] = tuple(band)
    out["damping_cutoff"] = soil_table.number(table, "damping_cutoff", "", lo=0.0, lo_open=False,
                                              default=DEFAULTS["damping_cutoff"])
    if 0.0 < out["damping_cutoff"] < band[1]:
        raise ConfigError("[soil] damping_cutoff %g Hz lies below the damping band's top (%g Hz): "
                          "give at least %g, or 0 for Rayleigh damping"
                          % (out["damping_cutoff"], band[1], band[1]))
    out["resolve_to"] = (soil_table.number(table, "resolve_to", "", lo=0.0) if "resolve_to" in table
                         else max(out["receivers"]))
    out["layers"] = soil_table.layers(table, damping_hi=1.0)
    out["measures"], out["variant"] = path_measures.parse(table)
    out["grounds"], out["ground"] = ground_shapes.parse(table)
    if "mitigation" in table:  # the mitigation study's load; the soil itself ignores it
        from .study_load import load_keys
        load_keys(table["mitigation"])
    above = sum(l.thickness for l in out["layers"][:-1])
    if above >= out["depth"]:
        raise ConfigError("[soil] depth %g m must exceed the layers above the last one (%g m)"
                          % (out["depth"], above))
    return out


def fine_depth(cfg):
    """The depth the graded mesh keeps the rule's spacing to (m): [soil]
    fine_depth, by default the Rayleigh wavelength of the softest layer at
    half f_max (20 elements of the rule), about as deep as the surface
    wave's motion reaches at the frequencies that carry it."""
    if cfg["fine_depth"] is not None:
        return cfg["fine_depth"]
    c_min = min(rayleigh_speed(l.shear_speed, l.poisson) for l in cfg["layers"])
    return 2.0 * c_min / cfg["f_max"]


def layered_nodes(layers, depth, h):
    """z node planes from -depth to 0, at most h apart, with a plane on every
    layer interface (the material is cell-wise)."""
    tops = [0.0]
    for layer in layers[:-1]:
        tops.append(tops[-1] - layer.thickness)
    tops.append(-depth)
    z = []
    for a, b in zip(tops[1:], tops[:-1]):  # bottom, top of each layer
        z.extend(uniform_nodes(a, b, h)[:-1])
    return sorted(z) + [0.0]


def graded_layer_nodes(layers, depth, f_max, n, growth, fine_depth=0.0):
    """z node planes of the graded mesh: in each layer above the last, at
    most h_k = c_R,k / (n f_max) apart (the mesh-size rule with that layer's
    own Rayleigh speed); in the last layer (the half-space) h_k from its top
    to `fine_depth` m below the surface, growing by `growth` per element
    below. Every layer interface is a node plane."""
    tops = [0.0]
    for layer in layers[:-1]:
        tops.append(tops[-1] - layer.thickness)
    z = [0.0]
    for k, layer in enumerate(layers):
        h_k = rayleigh_speed(layer.shear_speed, layer.poisson) / (n * f_max)
        top = tops[k]
        if k < len(layers) - 1:
            z.extend(uniform_nodes(tops[k + 1], top, h_k)[:-1])
        else:
            fine = max(h_k, fine_depth + top)
            z.extend(graded_nodes(-depth, top, top, h_k, fine, growth)[:-1])
    return sorted(z)


def block_params(cfg, footprints):
    """SoilParams for a half block (y >= 0, the track axis a symmetry plane)
    under the footprints (rc.Footprint of the interface, in the rail's frame):
    x shifted so that the rail's first footprint edge lies `margin` m from
    the block's end; receivers at (receiver_x, distance)."""
    if not footprints:
        raise ConfigError("no footprints")
    x0 = min(f.x - 0.5 * f.length for f in footprints)
    x1 = max(f.x + 0.5 * f.length for f in footprints)
    margin, along = cfg["margin"], cfg["margin_along"]
    length = (x1 - x0) + 2.0 * along
    width_track = max(f.y + 0.5 * f.width for f in footprints)
    half_width = max(max(cfg["receivers"]), width_track) + margin
    rx = 0.5 * (x0 + x1) if cfg["receiver_x"] is None else cfg["receiver_x"]
    if not x0 - along < rx < x1 + along:
        raise ConfigError("[soil] receiver_x %g m lies outside the block (%g to %g m along the "
                          "rail)" % (rx, x0 - along, x1 + along))
    fps = [Footprint(f.x - x0 + along, f.length, f.width, f.y) for f in footprints]
    p = SoilParams(length=length, half_width=half_width, depth=cfg["depth"],
                   layers=cfg["layers"], footprints=fps,
                   receivers=[(rx - x0 + along, d) for d in cfg["receivers"]],
                   f_max=cfg["f_max"], elements_per_wavelength=cfg["elements_per_wavelength"],
                   symmetric=True, damping_band=cfg["damping_band"],
                   damping_cutoff=cfg["damping_cutoff"],
                   static_reach=cfg["static_reach"],
                   footprint_compliance=cfg["footprint_compliance"])
    if cfg["mesh_size"] is not None:
        h = cfg["mesh_size"]
    else:
        c_min = min(rayleigh_speed(l.shear_speed, l.poisson) for l in cfg["layers"])
        h = c_min / cfg["f_max"] / cfg["elements_per_wavelength"]
    check_size(cfg, h, [length, half_width, cfg["depth"]])
    if cfg["growth"] > 1.0:
        g = cfg["growth"]
        across = min(cfg["resolve_to"], half_width)
        deep = min(fine_depth(cfg), cfg["depth"])
        p.x_nodes = graded_nodes(0.0, length, 0.5 * length, h, 0.5 * (x1 - x0), g)
        p.y_nodes = graded_nodes(0.0, half_width, 0.0, h, across, g)
        p.z_nodes = graded_layer_nodes(cfg["layers"], cfg["depth"], cfg["f_max"],
                                       cfg["elements_per_wavelength"], g, deep)
        # The graded zones are absorbing layers (fe_soil/absorbing.py).
        if cfg["absorbing_reflection"] < 1.0:
            p.absorbing = (along, along + (x1 - x0), across, -deep)
            p.absorbing_reflection = cfg["absorbing_reflection"]
    else:
        p.x_nodes = uniform_nodes(0.0, length, h)
        p.y_nodes = uniform_nodes(0.0, half_width, h)
        p.z_nodes = layered_nodes(cfg["layers"], cfg["depth"], h)
    # Every listed measure's faces are node planes, whichever the variant
    # builds: a study's variants share one mesh (path_measures.py).
    listed = cfg.get("measures", [])
    planes = [path_measures.place([m], listed, rx, x0 - along, p, fps, h)[0] for m in listed]
    if listed:
        c_min = min(rayleigh_speed(l.shear_speed, l.poisson) for l in cfg["layers"])
        rule = cfg["mesh_size"] is None
        path_measures.refine(p, planes, h, c_min, cfg["f_max"] if rule else None,
                             cfg["elements_per_wavelength"] if rule else None,
                             protect_z=layered_nodes(cfg["layers"], cfg["depth"], math.inf))
        built = path_measures.selected(listed, cfg.get("variant"))
        p.measures = path_measures.place(built, listed, rx, x0 - along, p, fps, h)
    _shape(p, cfg, h, fps, planes)
    check_size(cfg, h, [length, half_width, cfg["depth"]],
               [len(p.x_nodes) - 1, len(p.y_nodes) - 1, len(p.z_nodes) - 1])
    return p, x0 - along


def _shape(p, cfg, h, fps, measures):
    """The ground's shape of [soil] ground checked against the block and its
    node planes added (fe_soil/ground_shapes.py), those of the measures'
    faces kept."""
    g = ground_shapes.find(cfg.get("grounds", []), cfg.get("ground", ground_shapes.AT_GRADE))
    if g.shape == ground_shapes.AT_GRADE:
        return
    ground_shapes.check(g, cfg, p, fps)
    c_min = min(rayleigh_speed(l.shear_speed, l.poisson) for l in cfg["layers"])
    h_ground = h
    if g.material is not None:
        c = rayleigh_speed(g.material.shear_speed, g.material.poisson)
        h_ground = min(h, h * c / c_min if cfg["mesh_size"] is not None else
                       c / (cfg["elements_per_wavelength"] * cfg["f_max"]))
    faces_y = [q.y_lo for q in measures] + [q.y_hi for q in measures]
    faces_z = layered_nodes(cfg["layers"], cfg["depth"], math.inf) + [q.z_lo for q in measures]
    ground_shapes.refine(p, g, h, h_ground, protect_y=faces_y, protect_z=faces_z)
    p.ground = g


def memory_bytes():
    """The machine's physical memory (0 if unknown)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 0


def check_size(cfg, h, extents, elements=None):
    """Refuses, naming the key that sets the element size, a block of more
    than MAX_AXIS_ELEMENTS along an axis (before the node planes are listed;
    `elements` None: the uniform count at h, an upper bound) or, once they
    are listed (`elements` per axis), of more DOFs than the bound:
    MAX_DOFS, and no more than half the machine's memory at BYTES_PER_DOF."""
    key = ("[soil] mesh_size = %g m" % h if cfg["mesh_size"] is not None else
           "[soil] f_max = %g Hz with elements_per_wavelength = %g (elements of %.3g m)"
           % (cfg["f_max"], cfg["elements_per_wavelength"], h))
    if elements is None:
        ratios = [e / h for e in extents]  # inf for a subnormal h or a huge extent
        if not all(math.isfinite(r) and r <= MAX_AXIS_ELEMENTS for r in ratios):
            raise ConfigError(
                "%s gives %s elements along the block of %s m (its length: the track plus twice "
                "[soil] margin; its half width: the farthest of [soil] receivers and the track, "
                "plus margin; its height: [soil] depth); at most %d along an axis: raise the "
                "element size or shrink depth, margin or receivers" % (
                    key, " x ".join("%.4g" % max(1.0, r) for r in ratios),
                    " x ".join("%g" % e for e in extents), MAX_AXIS_ELEMENTS))
        return  # the node planes (graded: fewer) are counted once listed
    dofs = 3 * math.prod(n + 1 for n in elements)
    need = BASE_BYTES + BYTES_PER_DOF * dofs
    ram = memory_bytes()
    limit = min(MAX_DOFS, (ram // 2 - BASE_BYTES) // BYTES_PER_DOF if ram else MAX_DOFS)
    if dofs > limit:
        raise ConfigError("%s gives %s elements, %d DOFs, about %.1f GiB (%d KiB a DOF); this "
                          "machine holds %d DOFs (at most %d, and half its %.1f GiB): raise the "
                          "element size or shrink depth, margin or receivers" % (
                              key, " x ".join(map(str, elements)), dofs, need / 2**30,
                              BYTES_PER_DOF // 1024, limit, MAX_DOFS, ram / 2**30))


def channel_names(distances):
    """History channel names of the receivers' vertical velocity: r8m_vz_mps,
    r0p5m_vz_mps (a point for the decimal point); repeated distances get
    _2, _3 ... (names are unique)."""
    names = []
    for d in distances:
        base = "r%sm_vz_mps" % ("%g" % d).replace(".", "p").replace("-", "m").replace("+", "")
        name, k = base, 1
        while name in names:
            k += 1
            name = "%s_%d" % (base, k)
        names.append(name)
    return names
