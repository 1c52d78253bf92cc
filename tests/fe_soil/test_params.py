"""The sizing rules of the finite-element soil (pure Python)."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))
from fe_soil.params import (  # noqa: E402
    Layer, graded_nodes, mesh_size, rayleigh_coefficients, rayleigh_speed, resolved_frequency, sized_block)

SOFT = Layer(thickness=3.0, density=1800.0, shear_speed=120.0, poisson=1.0 / 3.0, damping=0.03)
STIFF = Layer(thickness=1.0, density=2000.0, shear_speed=250.0, poisson=0.25, damping=0.02)


class Params(unittest.TestCase):
    def test_rayleigh_speed_roots(self):
        self.assertAlmostEqual(rayleigh_speed(1.0, 0.25), math.sqrt(2.0 - 2.0 / math.sqrt(3.0)), delta=1e-9)
        # nu = 1/2: the root of xi^6 - 8 xi^4 + 24 xi^2 - 16 = 0, 0.9553.
        self.assertAlmostEqual(rayleigh_speed(1.0, 0.4999999), 0.95531, delta=1e-4)

    def test_block_is_sized_from_the_track_and_receivers(self):
        p = sized_block(30.0, [SOFT, STIFF], margin=6.0, depth=15.0, f_max=25.0)
        self.assertEqual((p.length, p.half_width, p.depth), (42.0, 38.0, 15.0))
        self.assertEqual(len(p.footprints), 51)
        self.assertAlmostEqual(p.footprints[-1].x, 36.0)
        self.assertEqual(p.receivers, [(21.0, 4.0), (21.0, 8.0), (21.0, 16.0), (21.0, 32.0)])
        # h = c_R(soft) / f_max / 12 elements per wavelength (the default).
        self.assertAlmostEqual(mesh_size(p), rayleigh_speed(120.0, 1.0 / 3.0) / 25.0 / 12.0, delta=1e-12)
        self.assertIs(p.layer_at(-2.9), SOFT)
        self.assertIs(p.layer_at(-3.1), STIFF)

    def test_rayleigh_damping_fits_both_frequencies(self):
        a0, a1 = rayleigh_coefficients(0.03, 5.0, 50.0)
        for f in (5.0, 50.0):
            w = 2.0 * math.pi * f
            self.assertAlmostEqual(a0 / (2.0 * w) + a1 * w / 2.0, 0.03, delta=1e-12)

    def test_resolved_frequency_falls_with_distance_and_h(self):
        f = [resolved_frequency(0.5, 1e-3, SOFT, d) for d in (4.0, 8.0, 16.0, 32.0)]
        self.assertTrue(all(a > b for a, b in zip(f, f[1:])), f)
        self.assertGreater(resolved_frequency(0.25, 5e-4, SOFT, 16.0), f[2])

    def test_graded_nodes(self):
        x = graded_nodes(0.0, 10.0, 5.0, 0.25, 1.0, 1.5)
        self.assertEqual((x[0], x[-1]), (0.0, 10.0))
        steps = [b - a for a, b in zip(x, x[1:])]
        self.assertTrue(all(s > 0 for s in steps))
        self.assertAlmostEqual(min(steps), 0.25)
        self.assertIn(5.0, x)


if __name__ == "__main__":
    unittest.main()
