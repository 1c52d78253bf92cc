"""How much of a load lies above the frequency a mesh resolves, so that a
record driven by content the mesh cannot carry is said so rather than
silently wrong."""
import math

import numpy as np


def energy_above(signal, dt, f):
    """The fraction of the energy of `signal` (sampled every dt s along its
    first axis, each column's mean removed; the columns' spectra summed, so
    each footprint's own force history counts, not their sum) above f Hz, from its discrete Fourier transform
    (zero-padded to four times its length so the split falls between close
    lines; each line stands for the band of its width around it, and the
    line the split falls in counts by the part above f). 0 for a constant
    signal."""
    x = np.asarray(signal, dtype=float).reshape(len(signal), -1)
    x = x - x.mean(axis=0)
    spec = (np.abs(np.fft.rfft(x, n=4 * len(x), axis=0)) ** 2).sum(axis=1)
    freq = np.fft.rfftfreq(4 * len(x), dt)
    total = spec.sum()
    if total <= 0.0:
        return 0.0
    width = freq[1] - freq[0]
    above = np.clip((freq + 0.5 * width - f) / width, 0.0, 1.0)
    return float((spec * above).sum() / total)


def ricker_energy_above(fc, f):
    """The closed form for a Ricker wavelet of centre frequency fc: its
    energy density is proportional to f^4 exp(-2 f^2 / fc^2), so with
    a = sqrt(2) f / fc the fraction above f is
    erfc(a) + 8 / (3 sqrt(pi)) exp(-a^2) (a^3 / 2 + 3 a / 4)."""
    a = math.sqrt(2.0) * f / fc
    return math.erfc(a) + 8.0 / (3.0 * math.sqrt(math.pi)) * math.exp(-a * a) * (
        0.5 * a**3 + 0.75 * a)


# A load whose energy above a receiver's resolved frequency exceeds this
# share is reported as reaching above what the mesh resolves there.
ABOVE_SHARE = 0.01


def load_verdicts(load, dt, distances, resolved):
    """Per receiver: (distance, resolved frequency, share of the load's
    energy above it, a sentence saying whether the record there is driven
    by content the mesh does not resolve)."""
    out = []
    for d, f in zip(distances, resolved):
        share = energy_above(load, dt, f)
        if f <= 0.0:
            text = ("%g m: the receiver lies in the absorbing layers, which damp its record: "
                    "nothing is resolved there (raise [soil] resolve_to beyond it)" % d)
        elif share > ABOVE_SHARE:
            text = ("%g m: the load has %.1f %% of its energy above the resolved %.3g Hz: "
                    "the record there is not resolved (refine the mesh: raise [soil] f_max)"
                    % (d, 100.0 * share, f))
        else:
            text = ("%g m: the load has %.2g %% of its energy above the resolved %.3g Hz "
                    "(at most %g %%): resolved" % (d, 100.0 * share, f, 100.0 * ABOVE_SHARE))
        out.append((d, f, share, text))
    return out
