"""Vibration measures of a velocity time series (numpy only).

- PPV: the peak particle velocity, max |v(t)| over the series (per
  component; of a 3-component series the largest component peak).
- One-third-octave velocity levels: base-10 bands, centre f_m = 10^(m/10) Hz,
  edges f_m 10^(-+1/20) (IEC 61260), m = 0..20 (1 to 100 Hz). The band RMS
  comes from the discrete Fourier transform (Parseval: the mean square of the
  series is the sum of its one-sided power spectrum), and the level is
  L_v = 20 log10(v_rms / 1e-9 m/s) dB.
- KB_F(t) and KB_Fmax as DIN 4150-2:1999-06 ("Erschuetterungen im Bauwesen -
  Teil 2: Einwirkungen auf Menschen in Gebaeuden") defines them: the velocity
  in mm/s is weighted by the KB filter, a first-order high pass
  H_KB(f) = 1 / sqrt(1 + (f0/f)^2), f0 = 5.6 Hz, to KB(t); the running RMS is
  KB_F(t) = sqrt( 1/tau * integral_0^t exp(-(t - s)/tau) KB(s)^2 ds ),
  tau = 0.125 s (time weighting "F"), and KB_Fmax = max_t KB_F(t).
  The filter is applied causally (bilinear transform, f0 pre-warped), the
  exponential average exactly for a piecewise-constant KB^2.
"""
from __future__ import annotations

import math

import numpy as np

V_REF = 1e-9  # m/s
KB_F0 = 5.6  # Hz
KB_TAU = 0.125  # s


def ppv(v):
    """Peak particle velocity of a series v[time] or v[time, component]."""
    return float(np.max(np.abs(np.asarray(v, dtype=float))))


def low_passed(v, dt, top_hz):
    """v with its content above top_hz taken out: unchanged up to a third
    of an octave below it (top_hz 2^(-1/3)), a cos^2 taper to zero at it, by
    FFT with the record padded to twice its length (no wrap-around of its
    end onto its start). top_hz <= 0 or not finite: v as it is."""
    v = np.asarray(v, dtype=float)
    if not (math.isfinite(top_hz) and top_hz > 0.0):
        return v.copy()
    n = len(v)
    spec = np.fft.rfft(v, 2 * n)
    f = np.fft.rfftfreq(2 * n, dt)
    f1 = top_hz * 2.0 ** (-1.0 / 3.0)
    s = np.clip((f - f1) / (top_hz - f1), 0.0, 1.0)
    return np.fft.irfft(spec * np.cos(0.5 * math.pi * s) ** 2, 2 * n)[:n]


def third_octave_bands(f_lo=1.0, f_hi=100.0):
    """(centres, lower edges, upper edges) of the base-10 one-third-octave
    bands whose exact centres lie in [f_lo, f_hi]."""
    m = np.arange(math.ceil(10 * math.log10(f_lo) - 1e-9), math.floor(10 * math.log10(f_hi) + 1e-9) + 1)
    fc = 10.0 ** (m / 10.0)
    return fc, fc * 10.0 ** (-1.0 / 20.0), fc * 10.0 ** (1.0 / 20.0)


def band_rms(v, dt, f_lo=1.0, f_hi=100.0):
    """(centres, RMS velocity per band) of a series sampled every dt."""
    v = np.asarray(v, dtype=float)
    n = len(v)
    spec = np.fft.rfft(v)
    power = np.abs(spec) ** 2 / n**2
    power[1:] *= 2.0
    if n % 2 == 0:
        power[-1] /= 2.0
    freq = np.fft.rfftfreq(n, dt)
    fc, lo, hi = third_octave_bands(f_lo, f_hi)
    rms = np.array([math.sqrt(power[(freq >= a) & (freq < b)].sum()) for a, b in zip(lo, hi)])
    return fc, rms


def third_octave_levels(v, dt, f_lo=1.0, f_hi=100.0):
    """(centres, levels in dB re 1e-9 m/s); an empty band gives -inf."""
    fc, rms = band_rms(v, dt, f_lo, f_hi)
    with np.errstate(divide="ignore"):
        return fc, 20.0 * np.log10(rms / V_REF)


def kb_weighting(v, dt, f0=KB_F0):
    """KB(t): the velocity (m/s) in mm/s through the first-order high pass
    s/(s + w0), discretised by the bilinear transform with w0 pre-warped."""
    x = np.asarray(v, dtype=float) * 1e3
    k = math.tan(math.pi * f0 * dt)  # pre-warped w0 dt / 2
    b0 = 1.0 / (1.0 + k)
    a1 = (1.0 - k) / (1.0 + k)
    y = np.zeros_like(x)
    for i in range(1, len(x)):
        y[i] = a1 * y[i - 1] + b0 * (x[i] - x[i - 1])
    if len(x):
        y[0] = b0 * x[0]
    return y


def kb_f(v, dt, tau=KB_TAU, f0=KB_F0):
    """KB_F(t), the running RMS of KB with time constant tau."""
    kb2 = kb_weighting(v, dt, f0) ** 2
    decay = math.exp(-dt / tau)
    out = np.zeros_like(kb2)
    acc = 0.0
    for i, e in enumerate(kb2):
        acc = decay * acc + (1.0 - decay) * e
        out[i] = acc
    return np.sqrt(out)


def kb_fmax(v, dt, tau=KB_TAU, f0=KB_F0):
    return float(np.max(kb_f(v, dt, tau, f0))) if len(v) else 0.0


def receiver_summary(v, dt, f_lo=1.0, f_hi=100.0):
    """The measures of one receiver's velocity v[time, 3] (m/s), sampled
    every dt: PPV of each component and of the largest, the band levels of
    each component, KB_Fmax of each component (DIN 4150-2 rates each
    direction on its own)."""
    v = np.asarray(v, dtype=float).reshape(len(v), -1)
    levels = [third_octave_levels(v[:, i], dt, f_lo, f_hi) for i in range(v.shape[1])]
    return {
        "ppv": ppv(v),
        "ppv_components": [ppv(v[:, i]) for i in range(v.shape[1])],
        "band_centres": levels[0][0].tolist() if levels else [],
        "band_levels": [lv.tolist() for _, lv in levels],
        "kb_fmax": [kb_fmax(v[:, i], dt) for i in range(v.shape[1])],
    }


def vibration_csv(names, xs, ys, summaries):
    """The text of vibration.csv: a row per receiver (its channel name, x
    along the rail, y its distance from the axis), PPV (largest component
    and each), KB_Fmax per component, the vertical one-third-octave levels."""
    centres = summaries[0]["band_centres"] if summaries else []
    head = ["receiver", "x_m", "y_m", "ppv_mps", "ppv_x_mps", "ppv_y_mps", "ppv_z_mps",
            "kb_fmax_x", "kb_fmax_y", "kb_fmax_z"] + ["Lv_z_%gHz_dB" % f for f in centres]
    rows = [",".join(head)]
    for name, x, y, r in zip(names, xs, ys, summaries):
        vals = [x, y, r["ppv"]] + r["ppv_components"] + r["kb_fmax"] + r["band_levels"][2]
        rows.append(",".join([name] + ["%.9g" % v for v in vals]))
    return "\n".join(rows) + "\n"


def with_resolved(text, bands):
    """vibration.csv's text with two columns after the others: resolved_from_hz
    and resolved_to_hz, the centres of the lowest and highest one-third-octave
    band the soil resolves at each receiver (bands: a (low, high) pair per
    row; nan when none is)."""
    lines = text.rstrip("\n").split("\n")
    lines[0] += ",resolved_from_hz,resolved_to_hz"
    for k, (lo, hi) in enumerate(bands):
        lines[k + 1] += ",%.9g,%.9g" % (lo, hi)
    return "\n".join(lines) + "\n"


def receivers_csv(names, t, v):
    """The text of receivers.csv: t and (vx, vy, vz) of each receiver
    (v[time, receiver, component]), one row per sample."""
    head = ["t_s"] + ["%s_%s_mps" % (n[:-len("_vz_mps")], c) for n in names
                      for c in ("vx", "vy", "vz")]
    lines = [",".join(head)]
    flat = np.asarray(v).reshape(len(t), -1)
    for k in range(len(t)):
        lines.append(",".join(["%.9g" % t[k]] + ["%.9g" % x for x in flat[k]]))
    return "\n".join(lines) + "\n"
