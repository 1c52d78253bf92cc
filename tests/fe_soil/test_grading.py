"""The graded mesh of the [soil] table (growth > 1): where the f_max rule
must hold it holds, every layer interface is a node plane, and outside the
fine zones the spacing grows by at most the given factor (pure Python)."""
import collections
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))
from fe_soil import config  # noqa: E402
from fe_soil.params import rayleigh_speed  # noqa: E402

FP = collections.namedtuple("FP", "x y length width")
TABLE = {
    "f_max": 20.0, "depth": 20.0, "margin": 8.0, "receivers": [4.0, 8.0, 16.0, 32.0],
    "growth": 1.25, "resolve_to": 16.0,
    "layers": [
        {"thickness": 1.4, "density": 1800.0, "shear_wave_speed": 128.0, "poisson": 0.375},
        {"thickness": 2.7, "density": 1800.0, "shear_wave_speed": 176.0, "poisson": 0.195},
        {"density": 1800.0, "shear_wave_speed": 355.0, "poisson": 0.478},
    ],
}
FOOTPRINTS = [FP(-2.1 + 0.6 * k, 0.65, 0.6, 1.3) for k in range(124)]
EPS = 1e-9


def steps(nodes):
    return [b - a for a, b in zip(nodes, nodes[1:])]


def h_rule(layer, f_max=20.0, n=config.DEFAULTS["elements_per_wavelength"]):
    return rayleigh_speed(layer.shear_speed, layer.poisson) / (n * f_max)


class Grading(unittest.TestCase):
    def setUp(self):
        self.cfg = config.parse(dict(TABLE))
        self.p, self.x_offset = config.block_params(self.cfg, FOOTPRINTS)
        self.h = min(h_rule(layer) for layer in self.cfg["layers"])

    def test_layer_interfaces_are_node_planes_and_each_layer_keeps_its_rule(self):
        z, layers = self.p.z_nodes, self.cfg["layers"]
        self.assertAlmostEqual(z[0], -20.0, delta=EPS)
        self.assertAlmostEqual(z[-1], 0.0, delta=EPS)
        top = 0.0
        for layer in layers[:-1]:
            bottom = top - layer.thickness
            self.assertTrue(any(abs(p - bottom) < EPS for p in z), (bottom, z))
            inside = [s for a, s in zip(z, steps(z)) if bottom - EPS <= a < top - EPS]
            self.assertTrue(inside)
            self.assertLessEqual(max(inside), h_rule(layer) + EPS)
            top = bottom
        # The half-space: its own rule at its top, then growth per element
        # downwards (the last element, at the bottom, may take up to 1.3 x
        # the next step, the rounding of graded_nodes).
        below = [s for a, s in zip(z, steps(z)) if a < top - EPS][::-1]
        self.assertLessEqual(below[0], h_rule(layers[-1]) + EPS)
        for s0, s1 in zip(below[:-2], below[1:-1]):
            self.assertLessEqual(s1, 1.25 * s0 + EPS)
        self.assertLessEqual(below[-1], 1.3 * 1.25 * below[-2] + EPS)
        # Far fewer planes than the uniform rule's.
        self.assertLess(len(z), 0.5 * 20.0 / self.h)

    def test_rule_holds_over_the_track_and_out_to_resolve_to(self):
        xs, ys = self.p.x_nodes, self.p.y_nodes
        x0 = min(f.x - 0.5 * f.length for f in FOOTPRINTS) - self.x_offset
        x1 = max(f.x + 0.5 * f.length for f in FOOTPRINTS) - self.x_offset
        fine_x = [s for a, s in zip(xs, steps(xs)) if a + s > x0 + EPS and a < x1 - EPS]
        self.assertLessEqual(max(fine_x), self.h + EPS)
        fine_y = [s for a, s in zip(ys, steps(ys)) if a < 16.0 - EPS]
        self.assertLessEqual(max(fine_y), self.h + EPS)
        self.assertEqual((xs[0], ys[0]), (0.0, 0.0))
        self.assertAlmostEqual(xs[-1], self.p.length, delta=EPS)
        self.assertAlmostEqual(ys[-1], self.p.half_width, delta=EPS)
        for nodes in (xs, ys):
            s = steps(nodes)
            self.assertTrue(all(v > 0.0 for v in s))
            # Neighbouring elements differ by at most the growth factor.
            ratios = [max(a / b, b / a) for a, b in zip(s, s[1:])]
            self.assertLessEqual(max(ratios[1:-1]), 1.25 + 1e-6)
            # The block's last element is what is left of the side
            # (graded_nodes): at most 1.3 x the next step, and at least 0.3
            # of the step before it (x at the default rule: 0.608 m after
            # 1.910, 0.32 of it; at 10 elements per wavelength all within
            # 1.25).
            for last, before in ((s[0], s[1]), (s[-1], s[-2])):
                self.assertLessEqual(last / before, 1.3 * 1.25 + 1e-6)
                self.assertGreaterEqual(last / before, 0.3 - 1e-9)
        # The 32 m receiver lies in the graded zone: coarser than the rule.
        self.assertGreater(max(steps(ys)), 2.0 * self.h)

    def test_the_study_reports_each_receivers_largest_element(self):
        # fe_soil.study: the element that limits a receiver is the largest on
        # its surface path from the track (along y from 0, along x where it
        # stands, and the top element's depth), not the first of the x axis.
        from fe_soil.resolution import largest_element_on_path
        x = np.concatenate([[0.0, 3.0], np.arange(5.0, 41.0, 0.5)])  # coarse margin first
        y = np.concatenate([np.arange(0.0, 16.01, 0.5), 16.0 + 0.5 * np.cumsum(1.25 ** np.arange(1, 8))])
        z = -np.array([20.0, 10.0, 5.0, 1.4, 0.8, 0.4, 0.0])
        self.assertEqual(largest_element_on_path((x, y, z), 20.2, 8.0), 0.5)
        self.assertEqual(largest_element_on_path((x, y, z), 20.2, 20.0), 0.5 * 1.25 ** 5)
        self.assertEqual(largest_element_on_path((x, y, z[:-1] + 0.4), 20.2, 4.0), 0.5)
        self.assertEqual(largest_element_on_path((x, y, z), 1.0, 4.0), 3.0)  # in the margin

    def test_growth_one_is_the_uniform_mesh(self):
        table = dict(TABLE, growth=1.0)
        p, _ = config.block_params(config.parse(table), FOOTPRINTS)
        for nodes in (p.x_nodes, p.y_nodes):
            s = steps(nodes)
            self.assertLess(max(s) - min(s), 1e-9)
            self.assertLessEqual(max(s), self.h + EPS)

    def test_growth_with_mesh_size_is_refused_naming_both(self):
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] growth.*mesh_size"):
            config.parse(dict(TABLE, mesh_size=0.5))
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] growth must be < 2"):
            config.parse(dict(TABLE, growth=2.5))


if __name__ == "__main__":
    unittest.main()
