"""The whole record of a surface receiver against Lamb's problem: the
closed form of Pekeris (fe_soil/lamb.py, nu = 1/4) for a vertical force
spread uniformly over a rectangular footprint, and the measures the
ground-vibration check compares (numpy only).

Over the whole record (from the load's start to the record's end, which
should lie after the slowest wave the block can send back has passed):
normalised RMS ||v - v_ref|| / ||v_ref||, PPV, KB_Fmax and the one-third-
octave levels (fe_soil/measures.py). Over the direct waves (up to the
first wave the block can send back): the arrival (the time of the peak
after the force's), the peak and the normalised RMS.
"""
from __future__ import annotations

import math

import numpy as np

from . import lamb, measures


def footprint_reference(t, receiver, footprint, mu, cs, force, fc, t0, gauss=(4, 16)):
    """Downward surface velocity (m/s) at `receiver` (x, y) under `force` N
    (positive down) with the time history of a Ricker of centre fc peaking
    at t0, spread uniformly over `footprint` (x, y, along, across): the point
    response averaged over the footprint by Gauss-Legendre (gauss points
    along, across)."""
    fx, fy, along, across = footprint
    _, df, d2f = lamb.ricker(fc, t0)
    qa, wa = np.polynomial.legendre.leggauss(gauss[0])
    qc, wc = np.polynomial.legendre.leggauss(gauss[1])
    out = np.zeros(len(t))
    for a, w1 in zip(0.5 * along * qa, 0.5 * wa):
        for c, w2 in zip(0.5 * across * qc, 0.5 * wc):
            r = math.hypot(receiver[0] - fx - a, receiver[1] - fy - c)
            out += w1 * w2 * lamb.convolve(np.asarray(t, dtype=float), r, mu, cs, df, d2f)
    return force * out


def peak(t, x):
    """(time, value) of the largest |x|, by a parabola through the top three."""
    y = np.abs(x)
    k = int(np.clip(np.argmax(y), 1, len(y) - 2))
    y0, y1, y2 = y[k - 1], y[k], y[k + 1]
    den = y0 - 2.0 * y1 + y2
    s = 0.5 * (y0 - y2) / den if den != 0.0 else 0.0
    return t[k] + s * (t[1] - t[0]), y1 - 0.25 * (y0 - y2) * s


def nrms(v, ref):
    return float(np.linalg.norm(v - ref) / np.linalg.norm(ref))


def band_errors(v, ref, dt, f_res, floor_db=30.0):
    """(centres, FE - reference level in dB) of the one-third-octave bands
    up to f_res Hz whose reference level lies within floor_db of the
    reference's highest band (the bands that carry the record)."""
    fc, lv = measures.third_octave_levels(v, dt, 1.0, 100.0)
    _, lr = measures.third_octave_levels(ref, dt, 1.0, 100.0)
    finite = np.isfinite(lr)
    keep = finite & (fc <= f_res * (1.0 + 1e-9)) & (lr >= np.max(lr[finite]) - floor_db)
    return fc[keep], lv[keep] - lr[keep]


def compare(t, v, ref, t0, direct_end, f_res):
    """The measures of the FE record v against the reference ref (both
    downward velocity at the times t, uniformly spaced from the load's
    start): a dict of the whole-record and direct-wave errors."""
    dt = t[1] - t[0]
    direct = t <= direct_end
    tf, pf = peak(t[direct], v[direct])
    tr, pr = peak(t[direct], ref[direct])
    centres, db = band_errors(v, ref, dt, f_res)
    return {
        "nrms": nrms(v, ref),
        "ppv": measures.ppv(v) / measures.ppv(ref) - 1.0,
        "kb": measures.kb_fmax(v, dt) / measures.kb_fmax(ref, dt) - 1.0,
        "band_db": float(np.max(np.abs(db))) if len(db) else 0.0,
        "band_at": float(centres[int(np.argmax(np.abs(db)))]) if len(db) else 0.0,
        "bands": (centres, db),
        "direct_nrms": nrms(v[direct], ref[direct]),
        "arrival": (tf - t0) / (tr - t0) - 1.0,
        "peak": pf / pr - 1.0,
    }


def direct_end(onset, r, extents, cs):
    """The load's onset plus the shortest shear-wave path from the source
    (at the surface, x in the middle of the block's length L, y = 0) via a
    side (x = 0 or L, y = W) or the bottom (z = -D) to the receiver r m
    across: the first wave reflected by the block that can be back."""
    L, W, D = extents
    paths = [2.0 * math.hypot(D, r / 2.0), 2.0 * W - r, 2.0 * math.hypot(L / 2.0, r / 2.0)]
    return onset + min(paths) / cs
