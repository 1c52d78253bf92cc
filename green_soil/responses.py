"""Footprint-to-footprint and footprint-to-point responses: their spectra
(greens.py), their static values, and the time-domain responses by inverse
FFT with an exponential window.

Exponential window (complex frequency): the spectra are computed at
w_n - i eta, w_n = 2 pi n / T; the inverse FFT of G(w - i eta) X(w - i eta)
is the response times exp(-eta t), so multiplying by exp(eta t) gives it
back with the wrap-around of the periodic FFT damped by exp(-eta T)
(E. Kausel and J. M. Roesset, "Frequency domain analysis of undamped
systems", J. Eng. Mech. 118(4) (1992) 721-734). The static part needs no
separate care then: no frequency is zero, the lowest is -i eta, and a
force that is switched on and held is represented by its damped spectrum
(the step response settles to G(0) within the record).
"""
from __future__ import annotations

import hashlib
import json
import math
import multiprocessing
import os
import sys
from dataclasses import dataclass

import numpy as np
from scipy import interpolate

from . import cache, greens
from .spectral import LOSS_ONSET, top_static


@dataclass(frozen=True)
class Footprint:
    """The sleeper's bearing rectangle: `along` (x) by `across` (y), m."""

    along: float
    across: float


def usable_cores():
    """The cores this process may run on (its affinity), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover (no affinity on this platform)
        return max(1, os.cpu_count() or 1)


# A pool of more processes than this many per usable core only costs memory
# and switching: a larger [soil] workers is held to it (workers = 256 on two
# cores once started 154 processes).
WORKERS_PER_CORE = 2


def worker_count(asked):
    """The processes a pool of `asked` workers starts (0: the usable cores):
    at most WORKERS_PER_CORE per usable core, with a note on stderr when the
    number asked is held to it."""
    cores = usable_cores()
    if asked == 0:
        return cores
    if asked > WORKERS_PER_CORE * cores:
        sys.stderr.write("green_soil: [soil] workers = %d held to %d (%d per usable core, %d cores)\n"
                         % (asked, WORKERS_PER_CORE * cores, WORKERS_PER_CORE, cores))
        return WORKERS_PER_CORE * cores
    return asked


def end_with_parent(parent):
    """A worker pool's initializer: the worker is sent SIGTERM when the
    process that started it ends (Linux prctl PR_SET_PDEATHSIG), so that a
    soil ended mid-build (a run that failed or was stopped) leaves no
    worker computing its block of frequencies; one whose parent is
    already gone exits at once."""
    try:
        import ctypes
        import signal

        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGTERM), 0, 0, 0)
    except (OSError, AttributeError):  # pragma: no cover (not Linux)
        pass
    if os.getppid() != parent:
        os._exit(1)


def worker_pool(n):
    """n worker processes (forked) that end with this process."""
    return multiprocessing.get_context("fork").Pool(n, end_with_parent, (os.getpid(),))


def _smooth_means(args):
    """The spline part of spectra() for one block of frequencies: the means
    of g - g_s over the footprint pairs and at the points (no Boussinesq
    part). A top-level function, so that worker processes can run it."""
    layers, fp, pair_offsets, point_offsets, omegas, d, f_grid = args
    a, b = fp.along, fp.across
    offsets = list(pair_offsets) + list(point_offsets)
    reach = max([math.hypot(abs(x) + a, abs(y) + b) for x, y in offsets] + [1.0])
    r = np.arange(0.0, reach + 4.0 * d.dr, d.dr)
    spline = interpolate.CubicSpline(r, greens.smooth_part(layers, omegas, r, d, f_grid=f_grid),
                                     axis=0)
    sx, wx = greens.tent_rule(a, d.quad_along)
    sy, wy = greens.tent_rule(b, d.quad_across)
    wq = np.outer(wx, wy).ravel()
    pairs = np.empty((len(pair_offsets), len(omegas)), complex)
    for i, (dx, dy) in enumerate(pair_offsets):
        pairs[i] = wq @ spline(np.hypot(dx + sx[:, None], dy + sy[None, :]).ravel())
    px, pwx = greens.box_rule(a, d.quad_along)
    py, pwy = greens.box_rule(b, d.quad_across)
    pw = np.outer(pwx, pwy).ravel()
    points = np.empty((len(point_offsets), len(omegas)), complex)
    for i, (dx, dy) in enumerate(point_offsets):
        points[i] = pw @ spline(np.hypot(dx + px[:, None], dy + py[None, :]).ravel())
    return pairs, points


def spectra(layers, fp: Footprint, pair_offsets, point_offsets, omegas,
            d: greens.Discretisation = greens.Discretisation(), workers=1):
    """(pairs, points): complex arrays (n, n_w) of the mean displacement over
    a footprint under a unit force spread over another offset by (dx, dy),
    and of the displacement at points offset (dx, dy) from a loaded
    footprint's centre, at the complex circular frequencies `omegas`.
    The frequencies are independent: `workers` processes (0: the usable
    cores) take contiguous blocks of them on the same wavenumber and radial
    grids, so the result does not depend on their number (to rounding in
    the linear algebra's blocking, far below 1e-12 relative)."""
    omegas = np.asarray(omegas, dtype=complex)
    f_grid = float(np.max(np.abs(omegas.real))) / (2.0 * math.pi) if len(omegas) else 0.0
    workers = worker_count(workers)
    blocks = [blk for blk in np.array_split(np.arange(len(omegas)), max(1, workers)) if len(blk)]
    jobs = [(layers, fp, list(pair_offsets), list(point_offsets), omegas[blk], d, f_grid)
            for blk in blocks]
    if len(jobs) > 1:
        with worker_pool(len(jobs)) as pool:
            parts = pool.map(_smooth_means, jobs, chunksize=1)
    else:
        parts = [_smooth_means(job) for job in jobs]
    pairs = np.concatenate([p for p, _ in parts], axis=1) if parts else np.empty(
        (len(pair_offsets), 0), complex)
    points = np.concatenate([q for _, q in parts], axis=1) if parts else np.empty(
        (len(point_offsets), 0), complex)
    a, b = fp.along, fp.across
    mu_scale = np.array([top_static(layers, w) for w in omegas])
    for i, (dx, dy) in enumerate(pair_offsets):
        pairs[i] += greens.static_pair(dx, dy, a, b) * mu_scale
    for i, (dx, dy) in enumerate(point_offsets):
        points[i] += greens.static_point(dx, dy, a, b) * mu_scale
    return pairs, points


@dataclass(frozen=True)
class Record:
    """The time axis: `dt` the output step, `duration` the length kept,
    `f_max` the highest frequency computed (a cosine taper from
    `taper` * f_max to f_max), `pad` the FFT period over the duration,
    `eta_t` = eta T, the window's decay over the FFT period."""

    dt: float
    duration: float
    f_max: float = 120.0
    taper: float = 0.8
    pad: float = 2.0
    eta_t: float = 10.0

    @property
    def n_fft(self):
        n = int(math.ceil(self.pad * self.duration / self.dt))
        return n + (n % 2)

    @property
    def period(self):
        return self.n_fft * self.dt

    @property
    def eta(self):
        return self.eta_t / self.period

    def frequencies(self):
        """The FFT bins up to f_max (Hz) and their complex circular frequencies."""
        f = np.arange(self.n_fft // 2 + 1) / self.period
        f = f[f <= self.f_max]
        return f, 2.0 * math.pi * f - 1j * self.eta

    def window(self, f):
        """1 below taper * f_max, a cosine half-bell to 0 at f_max."""
        lo = self.taper * self.f_max
        x = np.clip((f - lo) / (self.f_max - lo), 0.0, 1.0)
        return 0.5 * (1.0 + np.cos(math.pi * x))


def to_time(spec, rec: Record, force_spectrum):
    """Responses (n, n_t) kept over rec.duration: spec (n, n_w) times the
    damped force spectrum (n_w,), tapered, inverse FFT, times exp(eta t)."""
    f, _ = rec.frequencies()
    full = np.zeros((spec.shape[0], rec.n_fft // 2 + 1), complex)
    full[:, :len(f)] = spec * (force_spectrum * rec.window(f))[None, :]
    n_keep = int(round(rec.duration / rec.dt)) + 1
    t = np.arange(n_keep) * rec.dt
    x = np.fft.irfft(full, rec.n_fft, axis=1)[:, :n_keep] / rec.dt
    return t, x * np.exp(rec.eta * t)[None, :]


def ramp_responses(spec, rec: Record, n_steps):
    """(n, n_steps): the responses at t = dt, 2 dt, ..., n_steps dt to a
    unit force ramped from 0 to 1 over [0, dt] and held, from spec (n,
    n_w), tapered; n_steps at most rec.duration / dt.

    The ramp is a sum of unit hats (hat_spectrum), so its response is the
    running sum of the hat's response; the sum runs from the start of the
    FFT period, not from t = 0. Cut at f_max, a response is not causal:
    each hat's response rings before the hat begins (the taper's kernel is
    two-sided). That precursor sits at the end of the periodic inverse
    FFT, where exp(eta t) must be taken with t negative, and its sum is
    part of the ramp's response from t = 0 on: a velocity spectrum, which
    is not small at f_max, leaves a constant offset behind if it is
    dropped, and the running sum of the velocity then drifts away from the
    displacement without end (5 m from a 1 m square on a half-space: the
    integrated velocity at 1.4 and 3.0 times the static value 0.1 and
    0.5 s after the force was applied, the displacement on it)."""
    f, _ = rec.frequencies()
    n = rec.n_fft
    if not 0 < n_steps < n // 2 + 1:
        raise ValueError("ramp_responses: %d steps for an FFT period of %d samples"
                         % (n_steps, n))
    full = np.zeros((spec.shape[0], n // 2 + 1), complex)
    full[:, :len(f)] = spec * (hat_spectrum(rec) * rec.window(f))[None, :]
    x = np.fft.irfft(full, n, axis=1) / rec.dt
    # Samples 0..n_steps are t >= 0; the rest of the period is t < 0.
    idx = np.arange(n)
    t = np.where(idx <= n_steps, idx, idx - n) * rec.dt
    x *= np.exp(rec.eta * t)[None, :]
    ordered = np.concatenate([x[:, n_steps + 1:], x[:, :n_steps + 1]], axis=1)
    return np.cumsum(ordered, axis=1)[:, -n_steps:]


def damped_spectrum(samples, rec: Record):
    """The spectrum at the bins up to f_max of a force sampled every dt from
    t = 0 (samples beyond the FFT period ignored), damped by exp(-eta t)."""
    n = rec.n_fft
    x = np.zeros(n)
    m = min(n, len(samples))
    x[:m] = np.asarray(samples[:m], dtype=float)
    x *= np.exp(-rec.eta * np.arange(n) * rec.dt)
    f, _ = rec.frequencies()
    return np.fft.rfft(x)[:len(f)] * rec.dt


def hat_spectrum(rec: Record, derivative=False):
    """Spectrum of the unit hat of half-width dt centred at t = dt (the
    force rising over the first step and falling over the second; area dt)
    at the complex bins; times i w for its time derivative."""
    _, w = rec.frequencies()
    z = 0.5 * w * rec.dt
    sinc = np.where(np.abs(z) > 1e-8, np.sin(z) / np.where(z == 0, 1, z), 1.0)
    out = rec.dt * sinc**2 * np.exp(-1j * w * rec.dt)
    return out * (1j * w) if derivative else out


def cache_key(layers, fp, pair_offsets, point_offsets, rec, d, kind=None):
    extra = {} if kind is None else {"kind": kind}
    text = json.dumps({**extra,
        "layers": [[l.thickness, l.density, l.shear_speed, l.poisson, l.damping]
                   + list(getattr(l, "rayleigh_band", ())) for l in layers],
        "fp": [fp.along, fp.across], "pairs": [[float(v) for v in p] for p in pair_offsets],
        "points": [[float(v) for v in p] for p in point_offsets],
        "rec": [rec.dt, rec.duration, rec.f_max, rec.taper, rec.pad, rec.eta_t],
        "disc": list(d.key()), "loss_onset": LOSS_ONSET, "version": 2}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def default_cache_dir():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "railcosim", "green_soil")


def cached_spectra(layers, fp, pair_offsets, point_offsets, rec, d=greens.Discretisation(),
                   cache_dir=None, workers=1):
    """spectra() at rec's bins, kept in cache_dir (default
    $XDG_CACHE_HOME/railcosim/green_soil) under a hash of everything that
    enters them (not the number of workers); returns (pairs, points, hit).
    An entry is checked against its key before use (cache.py); a bad one,
    or a cache that cannot be written, costs the computation only."""
    cache_dir = cache_dir or default_cache_dir()
    key = cache_key(layers, fp, pair_offsets, point_offsets, rec, d)
    path = os.path.join(cache_dir, key + ".npz")
    _, w = rec.frequencies()
    shapes = [("pairs", (len(pair_offsets), len(w))), ("points", (len(point_offsets), len(w)))]
    got = cache.load(path, key, shapes)
    if got is not None:
        return got["pairs"], got["points"], True
    pairs, points = spectra(layers, fp, pair_offsets, point_offsets, w, d, workers)
    cache.store(cache_dir, path, key, [("pairs", pairs), ("points", points)])
    return pairs, points, False


def cached_horizontal(layers, fp, point_offsets, rec, d=greens.Discretisation(), cache_dir=None,
                      workers=1):
    """radial.point_means at rec's bins, (2, n_points, n_w): the x and y
    displacement at points offset (dx, dy) from a loaded footprint's
    centre; kept as cached_spectra keeps the vertical ones. Returns
    (spectra, hit)."""
    from . import radial

    cache_dir = cache_dir or default_cache_dir()
    key = cache_key(layers, fp, [], point_offsets, rec, d, kind="horizontal")
    path = os.path.join(cache_dir, key + ".npz")
    _, w = rec.frequencies()
    got = cache.load(path, key, [("horizontal", (2, len(point_offsets), len(w)))])
    if got is not None:
        return got["horizontal"], True
    out = np.asarray(radial.point_means(layers, fp, point_offsets, w, d, workers), dtype=complex)
    cache.store(cache_dir, path, key, [("horizontal", out)])
    return out, False
