"""A load's content above the resolved frequency (pure Python): the share
against the Ricker wavelet's closed form, and a 25 Hz Ricker on a mesh of
the 20 Hz rule reported as not resolved at every receiver."""
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))
from fe_soil import spectrum, study_report  # noqa: E402
from fe_soil.lamb import ricker  # noqa: E402
from fe_soil.params import Layer, rayleigh_speed, resolved_frequency  # noqa: E402

SOIL = Layer(thickness=20.0, density=2000.0, shear_speed=100.0, poisson=0.25, damping=0.0)
DISTANCES = (4.0, 8.0, 16.0)
DT = 1e-4


def ricker_load(fc):
    f, _, _ = ricker(fc, 0.2)
    return 1e4 * f(np.arange(int(round(1.0 / DT))) * DT)


def resolved_on_20hz_rule():
    """Each receiver's resolved frequency on the 20 Hz rule's mesh (10
    elements per Rayleigh wavelength), as the study states it: the lower of
    the 10-element frequency and the 45-degree phase estimate."""
    c = rayleigh_speed(SOIL.shear_speed, SOIL.poisson)
    h = c / 20.0 / 10.0
    return [min(c / (10.0 * h), resolved_frequency(h, 1e-4, SOIL, d)) for d in DISTANCES]


class Spectrum(unittest.TestCase):
    def test_share_above_matches_the_ricker_closed_form(self):
        for fc in (15.0, 25.0):
            for f in (10.0, 20.0, 40.0):
                exact = spectrum.ricker_energy_above(fc, f)
                self.assertAlmostEqual(spectrum.energy_above(ricker_load(fc), DT, f), exact,
                                       delta=2e-4, msg="fc %g, f %g" % (fc, f))
        # 25 Hz above 20 Hz: a = sqrt(2) 0.8, share 0.76743.
        self.assertAlmostEqual(spectrum.ricker_energy_above(25.0, 20.0), 0.767433, delta=1e-6)

    def test_25hz_ricker_on_a_20hz_mesh_is_reported_not_resolved(self):
        resolved = resolved_on_20hz_rule()
        self.assertTrue(all(f <= 20.0 + 1e-9 for f in resolved), resolved)
        verdicts = spectrum.load_verdicts(ricker_load(25.0), DT, DISTANCES, resolved)
        for (d, f, share, text), dist in zip(verdicts, DISTANCES):
            self.assertEqual(d, dist)
            self.assertGreaterEqual(share, spectrum.ricker_energy_above(25.0, 20.0) - 2e-4)
            self.assertIn("not resolved", text)
            self.assertIn("%.3g Hz" % f, text)
        line = study_report.load_content({"load_content": verdicts})
        self.assertEqual(line.count("not resolved"), len(DISTANCES), line)

    def test_slow_ricker_on_a_20hz_mesh_is_resolved(self):
        verdicts = spectrum.load_verdicts(ricker_load(5.0), DT, DISTANCES, resolved_on_20hz_rule())
        for _, f, share, text in verdicts:
            self.assertLess(share, spectrum.ABOVE_SHARE, f)
            self.assertNotIn("not resolved", text)
            self.assertIn(": resolved", text)

    def test_each_footprints_history_counts_not_their_sum(self):
        # Two footprints under opposite slow pulses and a small fast one on
        # the first: their sum holds only the fast pulse (its closed-form
        # share), each footprint mostly the slow one (the fast pulse has
        # about 1e-4 x 5/40 of its energy: a share near 1e-5).
        slow, fast = ricker_load(5.0), 1e-2 * ricker_load(40.0)
        loads = np.stack([slow + fast, -slow], axis=1)
        share = spectrum.energy_above(loads, DT, 20.0)
        self.assertLess(share, 1e-3)
        self.assertAlmostEqual(spectrum.energy_above(loads.sum(axis=1), DT, 20.0),
                               spectrum.ricker_energy_above(40.0, 20.0), delta=2e-4)


if __name__ == "__main__":
    unittest.main()
