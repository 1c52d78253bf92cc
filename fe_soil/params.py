"""Parameters of the finite-element soil and the rules that size its mesh.

Units are SI throughout. The block spans x in [0, length] along the track,
y in [0, half_width] across it (the track axis is y = 0, a symmetry plane
when the loading is symmetric; y in [-half_width, half_width] otherwise) and
z in [-depth, 0] (the surface is z = 0, z points up).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import List, Sequence, Tuple


@dataclass
class Layer:
    """One horizontal layer; `thickness` is ignored for the last layer,
    which reaches the bottom of the block."""

    thickness: float
    density: float  # kg/m^3
    shear_speed: float  # c_S, m/s
    poisson: float  # nu
    damping: float = 0.0  # material damping ratio xi (Rayleigh, see below)

    @property
    def shear_modulus(self) -> float:
        return self.density * self.shear_speed**2

    @property
    def p_speed(self) -> float:
        nu = self.poisson
        return self.shear_speed * math.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu))

    @property
    def lame_lambda(self) -> float:
        nu = self.poisson
        return 2.0 * self.shear_modulus * nu / (1.0 - 2.0 * nu)


@dataclass
class Footprint:
    """A sleeper's bearing area on the surface, centred at (x, y):
    `along` metres along the track, `across` metres across it."""

    x: float
    along: float
    across: float
    y: float = 0.0


@dataclass
class SoilParams:
    length: float
    half_width: float
    depth: float
    layers: List[Layer]
    footprints: List[Footprint] = field(default_factory=list)
    receivers: Sequence[Tuple[float, float]] = ()  # (x, y) surface points
    f_max: float = 20.0  # highest frequency of interest, Hz
    elements_per_wavelength: float = 12.0  # Q1, lumped mass (see mesh_size)
    symmetric: bool = True  # model y >= 0 with u_y = 0 on y = 0
    damping_band: Tuple[float, float] = (5.0, 50.0)  # Rayleigh fit, Hz
    # The stiffness-proportional damping acts on the velocity low-pass
    # filtered at this frequency (Hz; damping_law); 0: on the velocity itself
    # (the default is config.DEFAULTS' too).
    damping_cutoff: float = 100.0
    spring_alpha: Tuple[float, float] = (4.0 / 3.0, 2.0 / 3.0)  # (normal, tangential)
    dashpots: bool = True  # False: springs alone (a reflecting boundary, for comparison)
    cfl_safety: float = 0.8
    # Statics on the block extended by geometrically growing elements to
    # this many times its largest extent beyond it (fe_soil/far_field.py);
    # 0: statics on the block with its boundary springs.
    static_reach: float = 0.0
    # Absorbing layers (fe_soil/absorbing.py): the region of interest's faces
    # (x_lo, x_hi, y_hi, z_lo); mass-proportional damping grows from zero
    # there to the block's sides and bottom. None: no layers.
    absorbing: Tuple[float, float, float, float] | None = None
    absorbing_reflection: float = 1e-3  # the layers' nominal reflection
    # The static compliance the mesh cannot hold under each footprint, added
    # to its outputs (fe_soil/near_field.py); off: the FE alone.
    footprint_compliance: bool = False
    # Measures on the path (fe_soil/path_measures.py, placed in the block's
    # frame): trenches and walls whose cells take their own material.
    measures: Sequence = ()
    # The ground's shape (fe_soil/ground_shapes.py): None, flat at z = 0.
    ground: object = None
    # Optional explicit node coordinates per axis (graded meshes); when
    # given they override the mesh-size rule on that axis.
    x_nodes: Sequence[float] | None = None
    y_nodes: Sequence[float] | None = None
    z_nodes: Sequence[float] | None = None

    def layer_at(self, z: float) -> Layer:
        """The layer that contains depth -z (z <= 0)."""
        top = 0.0
        for layer in self.layers[:-1]:
            if -z < top + layer.thickness:
                return layer
            top += layer.thickness
        return self.layers[-1]


def rayleigh_speed(shear_speed: float, poisson: float) -> float:
    """c_R from the Rayleigh equation (xi = c_R/c_S):
    xi^6 - 8 xi^4 + (24 - 16 k) xi^2 + 16 (k - 1) = 0, k = (c_S/c_P)^2,
    the root in (0, 1), found by bisection."""
    k = (1.0 - 2.0 * poisson) / (2.0 * (1.0 - poisson))

    def f(x2: float) -> float:
        return x2**3 - 8.0 * x2**2 + (24.0 - 16.0 * k) * x2 + 16.0 * (k - 1.0)

    lo, hi = 1e-6, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(lo) * f(mid) <= 0.0:
            hi = mid
        else:
            lo = mid
    return shear_speed * math.sqrt(0.5 * (lo + hi))


def mesh_size(params: SoilParams) -> float:
    """The element size h = lambda_min / n: lambda_min = c_R,min / f_max is the
    shortest wavelength at the highest frequency of interest (the Rayleigh
    wave in the softest layer carries the surface vibration) and n the
    number of linear (Q1) elements per wavelength."""
    c_min = min(rayleigh_speed(l.shear_speed, l.poisson) for l in params.layers)
    return c_min / params.f_max / params.elements_per_wavelength


def uniform_nodes(a: float, b: float, h: float) -> List[float]:
    n = max(1, int(math.ceil((b - a) / h - 1e-9)))
    return [a + (b - a) * i / n for i in range(n + 1)]


def axis_nodes(params: SoilParams) -> Tuple[List[float], List[float], List[float]]:
    h = mesh_size(params)
    xs = list(params.x_nodes) if params.x_nodes is not None else uniform_nodes(0.0, params.length, h)
    y0 = 0.0 if params.symmetric else -params.half_width
    ys = list(params.y_nodes) if params.y_nodes is not None else uniform_nodes(y0, params.half_width, h)
    zs = list(params.z_nodes) if params.z_nodes is not None else uniform_nodes(-params.depth, 0.0, h)
    return xs, ys, zs


def damping_law(f1: float, f2: float, cutoff: float = 0.0) -> Tuple[float, float]:
    """(A0, A1): the damping C = xi (A0 M + A1 K) of a layer of damping ratio
    xi, matched at f1 and f2 (Hz). With cutoff = 0 it is Rayleigh damping,
    xi(w) = (A0/w + A1 w) xi / 2. With a cutoff f_c (>= f2) the stiffness
    part acts on the velocity low-pass filtered at f_c (first order, time
    constant tau = 1/(2 pi f_c)): its damping ratio is A1 g(w) xi / 2 with
    g(w) = w / (1 + (w tau)^2), which stops growing at f_c and falls above
    it, so it no longer bounds the explicit step (the filtered term adds at
    most A1 xi / tau to the stiffness there: docs/fe-soil.md,
    "Damping"). Solving the two matching conditions:
    A1 = 2 (w2 - w1) / (g2 w2 - g1 w1), A0 = A1 w1 w2 (g2 - g1) / (w2 - w1),
    Rayleigh's 2 / (w1 + w2) and 2 w1 w2 / (w1 + w2) at tau = 0."""
    w1, w2 = 2.0 * math.pi * f1, 2.0 * math.pi * f2
    if cutoff <= 0.0:
        return 2.0 * w1 * w2 / (w1 + w2), 2.0 / (w1 + w2)
    tau = 1.0 / (2.0 * math.pi * cutoff)
    g1, g2 = (w / (1.0 + (w * tau) ** 2) for w in (w1, w2))
    a1 = 2.0 * (w2 - w1) / (g2 * w2 - g1 * w1)
    return a1 * w1 * w2 * (g2 - g1) / (w2 - w1), a1


def rayleigh_coefficients(xi: float, f1: float, f2: float, cutoff: float = 0.0) -> Tuple[float, float]:
    """(a0, a1) of C = a0 M + a1 K with damping ratio xi at f1 and f2
    (xi(f) = a0/(2 w) + a1 w/2, below xi between f1 and f2); with a cutoff,
    the filtered law of damping_law."""
    if cutoff <= 0.0:  # Rayleigh's, in the form (and the rounding) of earlier versions
        w1, w2 = 2.0 * math.pi * f1, 2.0 * math.pi * f2
        return 2.0 * xi * w1 * w2 / (w1 + w2), 2.0 * xi / (w1 + w2)
    A0, A1 = damping_law(f1, f2, cutoff)
    return xi * A0, xi * A1


def stable_step(w_max, a1, tau):
    """The largest stable step of the scheme of run() for modes up to w_max
    (rad/s) under the stiffness-proportional damping a1 K, on the velocity
    (tau = 0) or filtered with time constant tau. Unfiltered: 2/w_max
    (sqrt(1 + xi^2) - xi), xi = a1 w_max / 2 the damping ratio at w_max.
    Filtered: the term adds up to a1/tau to the stiffness and keeps the
    ratio a1 w_max / (2 (1 + (w_max tau)^2)) at w_max, so w_max grows to
    w_max sqrt(1 + a1/tau) with that ratio. Both are checked against the
    spectral radius of the scheme's one-mode update (tests/fe_soil/
    test_damping_law.py): below it by at most 4 %."""
    if tau > 0.0:
        xi = 0.5 * a1 * w_max / (1.0 + (w_max * tau) ** 2)
        w_max *= math.sqrt(1.0 + a1 / tau)
    else:
        xi = 0.5 * a1 * w_max
    return 2.0 / w_max * (math.sqrt(1.0 + xi * xi) - xi)


def graded_nodes(a: float, b: float, centre: float, h_fine: float, fine_half: float,
                 growth: float = 1.25, h_max: float = math.inf) -> List[float]:
    """Node coordinates on [a, b]: spacing h_fine within fine_half of centre,
    growing by `growth` per element outside it, at most h_max."""

    def side(length: float) -> List[float]:
        out, x, h = [0.0], 0.0, h_fine
        while x < length - 1e-9:
            if x >= fine_half - 1e-9:
                h = min(h * growth, h_max)
            x = min(x + h, length)
            if length - x < 0.3 * h:
                x = length
            out.append(x)
        return out

    right = [centre + d for d in side(b - centre)] if b > centre else [centre]
    left = [centre - d for d in side(centre - a)][1:] if a < centre else []
    return sorted(set(left + right))


DEFAULT_RECEIVER_DISTANCES = (4.0, 8.0, 16.0, 32.0)  # m from the track axis


def sized_block(track_length: float, layers: List[Layer], sleeper_spacing: float = 0.6,
                footprint: Tuple[float, float] = (0.25, 2.6),
                distances: Sequence[float] = DEFAULT_RECEIVER_DISTANCES,
                margin: float = 8.0, depth: float = 20.0, f_max: float = 20.0,
                **kwargs) -> SoilParams:
    """A block under a straight track of `track_length` m: `margin` m beyond
    each end along the track and beyond the farthest receiver across it,
    `depth` m deep; one footprint (along x across) per sleeper; receivers
    at `distances` from the track axis beside the middle of the track."""
    length = track_length + 2.0 * margin
    n_sleepers = int(math.floor(track_length / sleeper_spacing + 1e-9)) + 1
    footprints = [Footprint(margin + i * sleeper_spacing, footprint[0], footprint[1])
                  for i in range(n_sleepers)]
    receivers = [(0.5 * length, d) for d in distances]
    return SoilParams(length=length, half_width=max(distances) + margin, depth=depth,
                      layers=layers, footprints=footprints, receivers=receivers,
                      f_max=f_max, **kwargs)


def resolved_frequency(h: float, dt: float, layer: Layer, distance: float,
                       phase_tolerance: float = math.pi / 4.0) -> float:
    """The highest frequency whose phase error after `distance` m stays
    within `phase_tolerance` (45 degrees by default), from the 1D dispersion
    of linear elements with a lumped mass and central differences,
    sin(w dt/2) = (c dt/h) sin(k_h h/2), at the layer's Rayleigh speed. An
    estimate: the 3D mesh adds direction-dependent error (measured in
    docs/fe-soil.md)."""
    c = rayleigh_speed(layer.shear_speed, layer.poisson)
    courant = c * dt / h

    def phase_error(f: float) -> float:
        w = 2.0 * math.pi * f
        s = math.sin(0.5 * w * dt) / courant
        if s >= 1.0:
            return math.inf
        k_h = 2.0 / h * math.asin(s)
        return abs(k_h - w / c) * distance

    lo, hi = 0.0, 0.5 / dt  # w dt / 2 < pi / 2
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if phase_error(mid) <= phase_tolerance:
            lo = mid
        else:
            hi = mid
    return lo
