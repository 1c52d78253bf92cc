"""Convergence in the discretisation: the default parameters
(greens.Discretisation, responses.Record) against finer ones on the
ground-vibration scene's layers, footprint to footprint (0 to 12 m, both
rails) and footprint to point (8 to 64 m), 1 to 100 Hz; and the time
record's window (eta T) and length."""
import unittest

import numpy as np

import support
from fe_soil import lamb
from green_soil import greens, responses as R

FP = R.Footprint(0.6, 1.3)
PAIRS = [(0.0, 0.0), (0.0, 1.3), (0.6, 0.0), (3.0, 1.3), (12.0, 0.0)]
POINTS = [(0.0, 8.0), (0.0, 16.0), (5.0, 32.0), (0.0, 64.0)]
REC = R.Record(dt=1e-3, duration=0.8, f_max=100.0)
FINER = {"k_ratio": 0.5, "dk_min": 0.5, "per_period": 2.0, "k_max_factor": 2.0, "dr": 0.5,
         "quad_along": 1.5, "quad_across": 1.5}


def refined(name):
    d = greens.Discretisation()
    value = getattr(d, name) * FINER[name]
    kw = {name: int(value) if isinstance(getattr(d, name), int) else value}
    return greens.Discretisation(**kw)


def worst(a, b):
    """max over offsets of max_f |a - b| / max_f |b|."""
    return float(np.max(np.abs(a - b).max(axis=1) / np.abs(b).max(axis=1)))


class Convergence(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        f, w = REC.frequencies()
        cls.w = w[(f >= 1.0)][::6]
        cls.base = R.spectra(support.LAYERED, FP, PAIRS, POINTS, cls.w)

    def test_each_parameter_refined(self):
        # Measured (each parameter refined alone): pairs below 4e-5, points
        # below 5.5e-4 (the wavenumber steps, at 64 m).
        for name in FINER:
            pairs, points = R.spectra(support.LAYERED, FP, PAIRS, POINTS, self.w, refined(name))
            self.assertLess(worst(self.base[0], pairs), 1e-3, name + " (pairs)")
            self.assertLess(worst(self.base[1], points), 1e-3, name + " (points)")

    def test_record_window_and_length(self):
        F, _, _ = lamb.ricker(25.0, 0.08)
        out = []
        for rec in (REC, R.Record(dt=1e-3, duration=0.8, f_max=100.0, eta_t=14.0, pad=3.0)):
            _, w = rec.frequencies()
            _, points = R.spectra(support.LAYERED, FP, [], POINTS[:2], w)
            t_fft = np.arange(rec.n_fft) * rec.dt
            out.append(R.to_time(points * (1j * w)[None, :], rec,
                                 R.damped_spectrum(F(t_fft), rec))[1])
        self.assertLess(worst(out[0], out[1]), 1e-3)


if __name__ == "__main__":
    unittest.main()
