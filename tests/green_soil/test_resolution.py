"""The bands the Green's-function soil resolves at a receiver
(green_soil/resolution.py), against values worked out here from the band
edges 10^((m -+ 1/2)/10) Hz: the taper from 0.8 f_max, the soil's window,
the record's line spacing and the receivers' memory after the Rayleigh
wave of the softest layer (its speed from the Rayleigh equation's cubic in
xi^2, solved here with numpy's polynomial roots, not the package's
bisection)."""
import math
import unittest

import numpy as np

import support  # noqa: F401  (skips without scipy; puts the checkout on the path)
from fe_soil.params import Layer  # noqa: E402
from green_soil import resolution  # noqa: E402

LINCENT = [Layer(1.4, 1800.0, 128.0, 0.375, 0.044), Layer(2.7, 1800.0, 176.0, 0.195, 0.038),
           Layer(1.0, 1800.0, 355.0, 0.478, 0.037)]


def band(m):
    return 10.0 ** (m / 10.0)


def rayleigh(c_s, nu):
    k = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))
    roots = np.roots([1.0, -8.0, 24.0 - 16.0 * k, 16.0 * (k - 1.0)])
    x2 = min(r.real for r in roots if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0)
    return c_s * math.sqrt(x2)


def cfg(f_max=120.0, receiver_memory=2.4):
    return {"f_max": f_max, "receiver_memory": receiver_memory, "layers": LINCENT}


class Resolution(unittest.TestCase):
    def test_train_scene(self):
        # f_max 120 Hz: the taper starts at 96 Hz; the 80 Hz band ends at
        # 89.1 Hz, the 100 Hz band at 112 Hz. 2.4 s: lines 0.417 Hz apart;
        # the 2 Hz band is 0.461 Hz wide, the 1.6 Hz band 0.367 Hz.
        for d in (8.0, 16.0, 32.0, 64.0):
            r = resolution.resolved(cfg(), 2.4, 1e-3, d)
            self.assertAlmostEqual(r["lo_Hz"], band(3), delta=1e-12)
            self.assertAlmostEqual(r["hi_Hz"], band(19), delta=1e-12)
            self.assertEqual(r["lo_why"], "the 2.4 s record")
            self.assertEqual(r["hi_why"], "the taper from 96 Hz (0.8 f_max)")
            self.assertEqual(resolution.cell(r), "2-79.4")

    def test_the_window_limits_the_top(self):
        # 5 ms: nothing above 100 Hz, below the taper's 120 Hz (f_max 150);
        # 8 ms: 62.5 Hz, so the 50 Hz band (upper edge 56.2 Hz) is the last.
        r = resolution.resolved(cfg(150.0), 2.4, 5e-3, 8.0)
        self.assertAlmostEqual(r["hi_Hz"], band(19), delta=1e-12)
        self.assertEqual(r["hi_why"], "the soil's window 0.005 s (1 / 2H = 100 Hz)")
        r = resolution.resolved(cfg(150.0), 2.4, 8e-3, 8.0)
        self.assertAlmostEqual(r["hi_Hz"], band(17), delta=1e-12)

    def test_the_receivers_memory_limits_the_far_bottom(self):
        c_r = rayleigh(128.0, 0.375)
        self.assertAlmostEqual(resolution.softest_rayleigh(LINCENT), c_r, delta=1e-6)
        for d in (8.0, 16.0, 32.0, 64.0, 100.0):
            held = 1.0 - d / c_r
            lowest = min(m for m in range(21) if band(m - 0.5) >= 1.0 / held)
            lowest = max(lowest, 3)  # the record's 2 Hz band
            r = resolution.resolved(cfg(receiver_memory=1.0), 2.4, 1e-3, d)
            self.assertAlmostEqual(r["lo_Hz"], band(lowest), delta=1e-12, msg=d)
            self.assertEqual("memory" in r["lo_why"], lowest > 3, (d, r))
        # 64 m: held 0.467 s, 1/held 2.14 Hz; the 2.5 Hz band starts at 2.24 Hz
        r = resolution.resolved(cfg(receiver_memory=1.0), 2.4, 1e-3, 64.0)
        self.assertAlmostEqual(r["lo_Hz"], band(4), delta=1e-12)
        # 130 m: the memory ends before the Rayleigh wave arrives
        r = resolution.resolved(cfg(receiver_memory=1.0), 2.4, 1e-3, 130.0)
        self.assertEqual(resolution.cell(r), "none")

    def test_a_short_record_resolves_no_band(self):
        # 0.02 s: lines 50 Hz apart, wider than every band to 100 Hz (23 Hz)
        r = resolution.resolved(cfg(150.0, 1.0), 0.02, 1e-4, 2.0)
        self.assertEqual(resolution.cell(r), "none")
        self.assertEqual(r["lo_why"], "the 0.02 s record")

    def test_vibration_csv_pairs_per_receiver(self):
        # What vibration.csv's resolved_from_hz, resolved_to_hz carry: 64 m
        # as above (the 2.5 Hz band, memory 1 s), 130 m nothing (nan).
        c = dict(cfg(receiver_memory=1.0), receivers=[8.0, 64.0, 130.0])
        pairs = resolution.receiver_bands(c, 2.4, 1e-3)
        np.testing.assert_allclose(pairs[0], (band(3), band(19)), rtol=1e-14)
        self.assertAlmostEqual(pairs[1][0], band(4), delta=1e-12)
        self.assertTrue(all(map(math.isnan, pairs[2])))


if __name__ == "__main__":
    unittest.main()
