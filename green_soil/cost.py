"""What a Green's-function soil's keys imply together, estimated before
anything is built, and refused when the machine cannot hold it or the
build would outlast the master's wait (numpy and the standard library).

Each key is bounded alone in config.py; their product is bounded here,
from the sizes of the arrays the soil allocates (greens.py, responses.py,
track.py, convolution.py; docs/green-soil.md, "Joint bounds"):

- the wavenumber grid of greens.k_grid: n_k points up to k_max (3 times
  the top layer's shear wavenumber at f_max, at least 8 / its thickness),
  the step at most dk_max = 2 pi / (8 r_max), r_max the farthest offset
  (the track's length, the receivers' distance); counted in closed form;
- the record: M = memory / H footprint steps, M_r = receiver_memory / H
  receiver steps, an FFT of n_fft = 2 max(M, M_r, 0.5 s / H) samples, n_w
  frequencies up to f_max;
- memory: the Green's functions (n_k n_w and n_r n_w complex numbers, n_r
  = r_max / 0.1 m radii), the ramp responses (offsets x n_fft), the two
  footprint kernels (8 M N^2 bytes each) and their spectra (16 (P/2 + 1)
  N^2 each, P the power of two from 2 M), the gather's copies (32 M N^2),
  the receivers' kernels and spectra (3 R N rows);
- work: the Hankel sums (2 n_r n_k n_w multiply-adds), the layered
  flexibility (about FLEX_COST per wavenumber, frequency and layer), the
  Bessel function (BESSEL_COST per radius and wavenumber and worker), the
  footprint quadrature (384 points per offset and frequency).
"""
from __future__ import annotations

import math
import os

import numpy as np

from fe_soil.soil_table import ConfigError

# Discretisation's defaults (greens.Discretisation; test_cost checks they agree).
K_RATIO, DK_MIN, PER_PERIOD, K_MAX_FACTOR, DR = 0.004, 2e-4, 8.0, 3.0, 0.1
QUAD_POINTS = 2 * 8 * 2 * 12  # the tent rules along and across (responses._smooth_means)
PAD, MIN_RECORD = 2.0, 0.5  # responses.Record.pad, track.MIN_RECORD

MAX_WAVENUMBERS = 2_000_000  # k_grid is a Python loop: about a second
MAX_FOOTPRINTS = 4000
# Work units: multiply-adds (the Hankel sums' matrix products), the
# flexibility and the Bessel function at their measured cost in them (one
# thread, load 12: 2.3 ns a multiply-add, 5.8 us a wavenumber and layer of
# the flexibility, 186 ns a J0). The train scene (682 footprints, receivers
# to 64 m, 241 frequencies, 9.8k wavenumbers) is 4.5e10 and was built in
# 200 to 320 s on a loaded two-core machine; 1.5e11 is about the 900 s the
# master waits for a soil it started.
FLEX_COST = 2500.0
BESSEL_COST = 80.0
MAX_WORK = 1.5e11
DEFAULT_BYTES = 8 << 30  # when the machine's memory is unknown


def machine_bytes():
    """Half the machine's physical memory (DEFAULT_BYTES if unknown)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2
    except (ValueError, OSError, AttributeError):  # pragma: no cover
        return DEFAULT_BYTES


def wavenumbers(dk_max, k_max, k_ratio=K_RATIO, dk_min=DK_MIN):
    """The number of points greens.k_grid makes: steps of dk_min up to
    dk_min / k_ratio, then growing by 1 + k_ratio up to dk_max / k_ratio,
    then dk_max up to k_max (an upper bound, within a few points)."""
    k1 = min(dk_min / k_ratio, k_max)
    if dk_max <= dk_min:
        return _count(k_max / dk_max)
    n = k1 / dk_min
    k2 = min(max(dk_max / k_ratio, k1), k_max)
    n += math.log(k2 / k1) / math.log1p(k_ratio) if k2 > k1 else 0.0
    n += max(k_max - k2, 0.0) / dk_max
    return _count(n)


def _count(n):
    """n + 2 points as an int; inf when n is not a finite size (a subnormal
    thickness or speed gives k_max = inf)."""
    return int(n) + 2 if n < 1e18 else math.inf


def _offsets(fps, receivers, horizontal=True):
    """(unique footprint pairs, unique receiver offsets, r_max) as track.py
    forms them (|dx|, |dy| to 1e-9 m)."""
    x = np.array([f[0] for f in fps])
    y = np.array([f[1] for f in fps])
    a, b = fps[0][2], fps[0][3]
    dx = np.abs(x[None, :] - x[:, None])
    pairs = np.concatenate([np.stack([dx, np.abs(y[None, :] - y[:, None])], -1).reshape(-1, 2),
                            np.stack([dx, np.abs(y[None, :] + y[:, None])], -1).reshape(-1, 2)])
    rec = np.array(receivers, dtype=float).reshape(-1, 2)
    pts = np.concatenate([np.stack([np.abs(rec[:, :1] - x[None, :]),
                                    np.abs(rec[:, 1:] - s * y[None, :])], -1).reshape(-1, 2)
                          for s in (1.0, -1.0)])
    every = np.concatenate([pairs, pts])
    reach = max(float(np.max(np.hypot(every[:, 0] + a, every[:, 1] + b))), 1.0)
    return _unique(pairs), _unique(pts), reach


def _unique(v):
    """The number of distinct rows of v (n, 2), to 1e-9."""
    if not len(v):
        return 0
    k = np.round(v * 1e9).astype(np.int64)
    k = k[np.lexsort((k[:, 1], k[:, 0]))]
    return 1 + int(np.count_nonzero(np.any(k[1:] != k[:-1], axis=1)))


def estimate(cfg, fps, receivers, H, end_time):
    """The sizes, bytes and work of a TrackSoil for these settings (the
    checked [soil] table cfg, footprints (x, y, along, across), receiver
    points (x, y), the step H and the run's end_time), as a dict."""
    layers, f_max = cfg["layers"], cfg["f_max"]
    N, R = len(fps), len(receivers)
    memory = min(cfg["memory"], end_time + H)
    r_memory = min(cfg["receiver_memory"], end_time + H)
    M = max(1, int(math.ceil(memory / H - 1e-9)))
    M_r = max(1, int(math.ceil(r_memory / H - 1e-9)))
    n_fft = int(math.ceil(PAD * max(max(M, M_r) * H, MIN_RECORD) / H))
    n_fft += n_fft % 2
    n_w = int(f_max * n_fft * H) + 1
    n_pairs, n_points, reach = _offsets(fps, receivers)
    r_max = reach + 4.0 * DR
    n_r = int(r_max / DR) + 1
    top = layers[0]
    k_shear = K_MAX_FACTOR * 2.0 * math.pi * f_max / top.shear_speed
    k_thick = 8.0 / top.thickness if len(layers) > 1 else 0.0
    dk_max = 2.0 * math.pi / (PER_PERIOD * max(r_max, 1.0))
    n_k = wavenumbers(dk_max, max(k_shear, k_thick))
    workers = cfg["workers"] or max(1, len(os.sched_getaffinity(0)))
    rows = 3 * R
    spectrum = lambda m: (1 << int(math.ceil(math.log2(2 * m)))) // 2 + 1 if m >= 64 else 0  # noqa: E731
    n_off = n_pairs + 3 * n_points
    green = 16 * n_w * (n_k + 5 * n_r + n_pairs + 3 * n_points) + 8 * 256 * n_k * min(workers, n_w)
    kernels = 16 * M * N * N + 8 * M_r * rows * N
    spectra = 32 * spectrum(M) * N * N + 16 * spectrum(M_r) * rows * N
    transient = max(32 * M * N * N, 8 * 2 * (spectrum(M) - 1) * N * N) + 40 * n_off * n_fft
    work = (2.0 * n_r * n_k * n_w + FLEX_COST * n_k * n_w * len(layers)
            + BESSEL_COST * n_r * n_k * min(workers, n_w) + 2.0 * QUAD_POINTS * n_off * n_w)
    return {"N": N, "R": R, "M": M, "M_r": M_r, "n_fft": n_fft, "n_w": n_w, "n_k": n_k,
            "n_r": n_r, "r_max": r_max, "k_shear": k_shear, "k_thick": k_thick,
            "dk_max": dk_max, "bytes": green + kernels + spectra + transient,
            "kernel_bytes": kernels + spectra, "work": work}


def check(cfg, fps, receivers, H, end_time):
    """Refuses (ConfigError naming the keys) settings whose soil would not
    fit half the machine's memory or take longer to build than the master
    waits; returns the estimate."""
    if len(fps) > MAX_FOOTPRINTS:
        raise ConfigError("[soil] the track has %d footprints; the Green's-function soil holds "
                          "at most %d (its kernels grow as their square): use a shorter track "
                          "([sleepers] count)" % (len(fps), MAX_FOOTPRINTS))
    if not (0.0 < H < math.inf and 0.0 <= end_time < math.inf):
        raise ConfigError("[soil] the run's macro step %r s and end time %r s leave its memory "
                          "in steps undefined (the master sends H > 0 and a finite end time)"
                          % (H, end_time))
    e = estimate(cfg, fps, receivers, H, end_time)
    top = cfg["layers"][0]
    grid = ("k_max = %.3g rad/m (%s) in steps of at most %.3g rad/m (2 pi / (8 r_max), r_max = "
            "%.4g m from the track's length and [soil] receivers)"
            % (max(e["k_shear"], e["k_thick"]),
               "8 / the top layer's thickness = %g m" % top.thickness if e["k_thick"] > e["k_shear"]
               else "3 x 2 pi f_max / c_S: [soil] f_max = %g Hz, the top layer's shear_wave_speed = "
                    "%g m/s" % (cfg["f_max"], top.shear_speed), e["dk_max"], e["r_max"]))
    if e["n_k"] > MAX_WAVENUMBERS:
        raise ConfigError("[soil] the Green's functions need %.3g wavenumbers (at most %d): %s; "
                          "raise [[soil.layers]] thickness or shear_wave_speed of the top layer, "
                          "or lower [soil] f_max or receivers" % (e["n_k"], MAX_WAVENUMBERS, grid))
    limit = machine_bytes()
    if e["bytes"] > limit:
        raise ConfigError(
            "[soil] this soil would hold about %.1f GiB (%.1f GiB of kernels and their spectra: %d "
            "footprints, M = %d steps of [soil] memory = %g s and %d of receiver_memory = %g s at "
            "H = %g s, the run's end_time %g s; %d frequencies to f_max, %d wavenumbers); this "
            "machine holds %.1f GiB (half its memory): lower [soil] memory, receiver_memory or "
            "f_max, or shorten the run" % (e["bytes"] / 2**30, e["kernel_bytes"] / 2**30, e["N"],
                                           e["M"], cfg["memory"], e["M_r"], cfg["receiver_memory"],
                                           H, end_time, e["n_w"], e["n_k"], limit / 2**30))
    if e["work"] > MAX_WORK:
        raise ConfigError(
            "[soil] the Green's functions would take about %.2g operations (at most %.2g, about the "
            "900 s the master waits): %d wavenumbers (%s), %d radii to %.4g m, %d frequencies to "
            "[soil] f_max = %g Hz over a %g s record ([soil] memory, receiver_memory); lower [soil] "
            "receivers or f_max, or raise the top layer's shear_wave_speed or thickness"
            % (e["work"], MAX_WORK, e["n_k"], grid, e["n_r"], e["r_max"], e["n_w"], cfg["f_max"],
               e["n_fft"] * H / PAD))
    return e
