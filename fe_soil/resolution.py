"""What the FE soil resolves at each receiver, and the one-third-octave
bands that follows: what its study's report and vibration.csv state.

- Above: the mesh. A wave from the track to a receiver crosses elements
  up to h (largest_element_on_path); the frequency with 10 such elements
  per Rayleigh wavelength of the softest layer, c_R / (10 h), and the
  45-degree phase estimate over the distance (params.resolved_frequency)
  bound it; the lower of the two is the receiver's resolved frequency. A
  receiver inside the absorbing layers has none (they damp it).
- The bands: the highest resolved band is the highest whose upper edge lies
  at or below the resolved frequency; the lowest is the lowest whose width
  holds a spectral line of the T-second record (1/T at most its width,
  docs/fe-soil.md, "Vibration measures").
"""
from __future__ import annotations

import math

import numpy as np

from .measures import third_octave_bands


def largest_element_on_path(nodes, x, y):
    """The largest element edge a wave crosses on the surface from the track
    axis (y = 0) to the receiver at (x, y): along y over [0, y], along x at
    x, and the top element's depth (nodes: the x, y, z node coordinates;
    z = 0 is the surface)."""
    xs, ys, zs = (np.asarray(n, dtype=float) for n in nodes)
    hy = np.diff(ys)[ys[:-1] < y].max(initial=0.0)
    k = min(max(int(np.searchsorted(xs, x)) - 1, 0), len(xs) - 2)
    hx = xs[k + 1] - xs[k]
    top = np.sort(zs)
    return float(max(hx, hy, top[-1] - top[-2]))


def resolution(soil, cfg):
    """(c_R of the softest layer, [per receiver: (the largest element on its
    path, the frequency with 10 such elements per Rayleigh wavelength, the
    45-degree phase-error estimate)]). A graded mesh keeps the rule's size
    out to resolve_to and grows beyond it, so each receiver has its own; a
    receiver inside its absorbing layers has none (0 Hz: they damp it)."""
    from .absorbing import inside
    from .params import rayleigh_speed, resolved_frequency

    soft = min(cfg["layers"], key=lambda l: rayleigh_speed(l.shear_speed, l.poisson))
    c = rayleigh_speed(soft.shear_speed, soft.poisson)
    out = []
    for (x, y), d in zip(soil.p.receivers, cfg["receivers"]):
        h = largest_element_on_path(soil.nodes, x, y)
        if inside(soil.p, soil.nodes, (x, y, 0.0)):
            out.append((h, 0.0, 0.0))
        else:
            out.append((h, c / (10.0 * h), resolved_frequency(h, soil.dt, soft, d)))
    return c, out


def resolved_frequencies(soil, cfg):
    """Each receiver's resolved frequency (Hz; 0 where nothing is)."""
    return [min(f, g) for _, f, g in resolution(soil, cfg)[1]]


def receiver_bands(soil, cfg, record_s):
    """resolved_bands at each receiver of the FE soil (model.FESoil) for a
    record of record_s seconds."""
    return [resolved_bands(f, record_s) for f in resolved_frequencies(soil, cfg)]


def resolved_bands(top_hz, record_s):
    """(lowest, highest) centre of the one-third-octave bands (1-100 Hz)
    resolved below top_hz in a record of record_s seconds; (nan, nan) when
    none is."""
    fc, lo, hi = third_octave_bands()
    ok = [f for f, a, b in zip(fc, lo, hi) if b - a >= 1.0 / record_s and b <= top_hz + 1e-9]
    return (float(ok[0]), float(ok[-1])) if ok else (math.nan, math.nan)
