"""The one-third-octave bands the Green's-function soil resolves at a
receiver, and why: what its study's report states per receiver.

- Above: the Green's functions are cut by a cosine taper from 0.8 f_max
  to f_max (responses.py), and the forces reach the soil at its own
  window H (sampled there: nothing above 1 / (2 H) exists). The highest
  resolved band is the highest whose upper edge lies at or below
  min(0.8 f_max, 1 / (2 H)).
- Below: the record of T seconds has spectral lines 1/T apart; a band of
  width 0.23 f_m always holds one when 1/T is at most its width (the rule
  docs/fe-soil.md gives under "Vibration measures"). And where the
  receivers' memory T_r is shorter than the record, their kernels stop
  T_r after each force increment: at a receiver d metres away the slowest
  surface wave (the Rayleigh wave of the softest layer, c_R) arrives
  d / c_R after it, so what follows it is held over T_r - d / c_R: an
  estimate, taken as resolving the bands whose lower edge is at least
  1 / (T_r - d / c_R). The lowest resolved band is the lowest that meets
  both.
"""
from __future__ import annotations

import math

from fe_soil.measures import third_octave_bands
from fe_soil.params import rayleigh_speed

TAPER_START = 0.8  # responses.py: the cosine taper runs from 0.8 f_max to f_max


def softest_rayleigh(layers):
    """The lowest Rayleigh wave speed among the layers (m/s)."""
    return min(rayleigh_speed(l.shear_speed, l.poisson) for l in layers)


def resolved(cfg, record_s, window_s, distance):
    """(lowest, highest) resolved band centre at a receiver `distance` m
    from the track axis, with the reason for each, as a dict: lo_Hz, hi_Hz
    (None when no band is resolved), lo_why, hi_why. cfg: the parsed [soil]
    table (green_soil.config.parse); record_s: the record's length;
    window_s: the soil's macro step."""
    top = min(TAPER_START * cfg["f_max"], 0.5 / window_s)
    hi_why = ("the taper from %.3g Hz (0.8 f_max)" % (TAPER_START * cfg["f_max"])
              if TAPER_START * cfg["f_max"] <= 0.5 / window_s else
              "the soil's window %.3g s (1 / 2H = %.4g Hz)" % (window_s, 0.5 / window_s))
    fc, lo_edge, hi_edge = third_octave_bands()
    # The lowest band with a line always in it, and the highest below `top`.
    ok = [f for f, a, b in zip(fc, lo_edge, hi_edge) if b - a >= 1.0 / record_s and b <= top + 1e-9]
    out = {"lo_Hz": float(ok[0]) if ok else None, "hi_Hz": float(ok[-1]) if ok else None,
           "lo_why": "the %.4g s record" % record_s, "hi_why": hi_why}
    memory = min(cfg["receiver_memory"], record_s)
    if memory >= record_s or not ok:
        return out
    c_r = softest_rayleigh(cfg["layers"])
    held = memory - distance / c_r
    kept = [f for f, a in zip(fc, lo_edge) if f in ok and held > 0.0 and a >= 1.0 / held]
    if not kept or kept[0] > out["lo_Hz"]:
        out["lo_why"] = ("the receivers' memory %.4g s (%.3g s after the Rayleigh wave at "
                         "%.4g m/s)" % (memory, held, c_r))
        out["lo_Hz"] = float(kept[0]) if kept else None
        out["hi_Hz"] = out["hi_Hz"] if kept else None
    return out


def receiver_bands(cfg, record_s, window_s):
    """(lowest, highest) resolved band centre at each receiver of cfg (nan
    for none): vibration.csv's resolved_from_hz, resolved_to_hz."""
    out = []
    for d in cfg["receivers"]:
        r = resolved(cfg, record_s, window_s, d)
        out.append((math.nan, math.nan) if r["lo_Hz"] is None else (r["lo_Hz"], r["hi_Hz"]))
    return out


def cell(r):
    """The report's cell: 'lo-hi' in Hz (band centres), or 'none'."""
    if r["lo_Hz"] is None:
        return "none"
    return "%.3g-%.3g" % (r["lo_Hz"], r["hi_Hz"])
