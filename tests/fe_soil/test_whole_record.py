"""The whole record on the graded mesh of the scene keys: the homogeneous
half-space (c_S = 100 m/s, rho = 2000, nu = 1/4, no damping) under a
10 kN 7.5 Hz Ricker on the middle one of 21 sleepers' 0.25 x 2.5 m
footprints, at f_max 10 Hz with the keys' defaults otherwise (absorbing
layers over the graded zones, growth 1.1), the vertical velocity from the
load's start to 0.6 s (after the slowest wave the block can send back has
passed) against the closed form of Pekeris averaged over the footprint
(pekeris_record.py). On the default block at 4 and 8 m; on the
same mesh without the layers (absorbing_reflection = 1, the viscous-spring
boundary alone) more comes back (the layers' share), and the previous rule
(10 elements per wavelength, growth 1.25, the rule's spacing to the
half-space's top only, no layers) fails the bound.

Every bound of issue 38 at 4, 8 and 16 m (ScaledBlock) on the CI-sized
counterpart of scenes/ground_vibration.toml's block. This test runs at
half the scene's f_max and Ricker frequency, so every wavelength is twice
as long and the lowest band judged moves from 5 Hz to 3.16 Hz: the block
must be about 5/3.16 = 1.6 times as large in metres to be the same block
in wavelengths. The scene's depth 30 and margin_along 12 become 48 and 19,
rounded up to 50 and 20 (resolve_to 18 stays: it places the 16 m receiver
inside the layers' face; margin stays 8: the layers across the track, from
resolve_to to the farthest receiver plus margin, are 22 m thick already,
and margin 12 changes the 16 m band by 0.01 dB). On the scene's block in
metres the 16 m receiver's lowest band fails (3.6 dB at 3.16 Hz). At full
size, the scene's block with resolve_to 20 is test_whole_record_full.py."""
import math
import unittest
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE
from pekeris_record import BOUNDS, F, MIDDLE, block
from pekeris_record import whole_record as record

from fe_soil import absorbing, config, lamb, resolution, spectrum

FC = 7.5
NEAR, ALL = (4.0, 8.0), (4.0, 8.0, 16.0)
# The scene's block keys and their CI-sized counterpart (the docstring).
SCENE_BLOCK = {"depth": 30.0, "margin_along": 12.0, "resolve_to": 18.0}
SCALED_BLOCK = {"depth": 50.0, "margin_along": 20.0, "resolve_to": 18.0}


def whole_record(p, judged=NEAR):
    """({distance: measures} at the receivers `judged` m across, the soil)
    under the 7.5 Hz Ricker."""
    return record(p, judged, FC)


class WholeRecord(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.layers, cls.soil = whole_record(block())
        cls.bare, cls.bare_soil = whole_record(block(absorbing_reflection=1.0))

    def test_absorbing_layers_pass_the_whole_record(self):
        # Measured (90,396 DOFs, dt 3.582 ms) at 4 / 8 m: nRMS 0.107 /
        # 0.171, PPV +1.0 % / -1.3 %, KB_Fmax +0.9 % / -0.6 %; direct waves:
        # peak +0.7 % / -1.4 %, nRMS 0.027 / 0.044 (the arrival, +1.55 % /
        # +0.80 %, is not asserted on this coarse CI mesh: +2.2 % / +1.8 %
        # at 10 elements per wavelength). The band levels are not asserted
        # here: the lowest bands (3-6 Hz) are off by 2.8 / 5.3 dB
        # (ScaledBlock: a deeper block with longer layers).
        for r, m in self.layers.items():
            msg = f"{r} m: {m}"
            self.assertLess(m["nrms"], 0.25, msg)
            self.assertLess(abs(m["ppv"]), 0.05, msg)
            self.assertLess(abs(m["kb"]), 0.10, msg)
            self.assertLess(abs(m["peak"]), 0.10, msg)
            self.assertLess(m["direct_nrms"], 0.15, msg)

    def test_the_layers_take_out_what_the_mesh_alone_sends_back(self):
        # The same mesh without the layers: nRMS 0.138 / 0.237 at 4 / 8 m
        # (0.77 and 0.72 of it with them).
        for r in self.layers:
            self.assertLess(self.layers[r]["nrms"], 0.85 * self.bare[r]["nrms"],
                            f"{r} m: {self.layers[r]['nrms']} against {self.bare[r]['nrms']}")

    def test_the_default_block_misses_the_lowest_bands(self):
        # The bands up to f_max (3.16 to 10 Hz here) whose reference level
        # lies within 30 dB of the highest: on the default block the lowest
        # is 2.76 / 5.31 dB off at 4 / 8 m (3.16 Hz, what comes back from
        # the bottom, 1.6 m below fine_depth at this f_max, and the track's
        # ends; ScaledBlock below meets 1 dB).
        for r, m in self.layers.items():
            self.assertGreater(m["band_db"], 2.5, f"{r} m: bands {m['bands']}")

    def test_the_previous_rule_fails(self):
        # 10 elements per wavelength, growth 1.25, the rule's spacing to the
        # top of the half-space only, no layers (the scene's mesh before):
        # nRMS 0.326 / 0.476 at 4 / 8 m (at 12 elements per wavelength
        # 0.417 / 0.638).
        old = whole_record(block(elements_per_wavelength=10.0, growth=1.25, fine_depth=0.0,
                                 absorbing_reflection=1.0))[0]
        self.assertAlmostEqual(old[8.0]["nrms"], 0.476, delta=0.02)
        self.assertGreater(min(m["nrms"] for m in old.values()), 0.25, old)

    def test_the_layers_change_neither_the_step_nor_the_statics(self):
        # Mass-proportional damping, diagonal and taken at the end of the
        # step: the same stable step and the same static state, bitwise.
        self.assertEqual(self.soil.dt, self.bare_soil.dt)
        forces = np.zeros(21)
        forces[MIDDLE] = F
        np.testing.assert_array_equal(self.soil.statics(forces), self.bare_soil.statics(forces))
        self.assertGreater(np.max(self.soil.c), np.max(self.bare_soil.c))


class ScaledBlock(unittest.TestCase):
    """Issue 38's bounds at 4, 8 and 16 m on the CI-sized counterpart of the
    scene's block (SCALED_BLOCK, the module's docstring)."""

    @classmethod
    def setUpClass(cls):
        cls.scaled = whole_record(block(**SCALED_BLOCK), ALL)[0]

    def test_every_bound_at_4_8_and_16_m(self):
        # Measured (211,302 DOFs, dt 3.582 ms) at 4 / 8 / 16 m: nRMS 0.022 /
        # 0.038 / 0.088, PPV +0.9 / -1.5 / -1.3 %, KB_Fmax +1.0 / -0.6 /
        # +0.9 %, worst band 0.15 / 0.09 / 0.41 dB (3.16 Hz); direct waves:
        # arrival +1.50 / +0.83 / +1.01 %, peak +0.6 / -1.6 / -0.7 %, nRMS
        # 0.021 / 0.038 / 0.088 (at 10 elements per wavelength, 138,996
        # DOFs: nRMS 0.022 / 0.065 / 0.119, worst band 0.09 / 0.07 / 0.40
        # dB, arrival +1.54 / +1.54 / +1.28 %).
        self.assertEqual(sorted(self.scaled), list(ALL))
        for r, m in self.scaled.items():
            # the five bands from 3.16 to 10 Hz are judged at each receiver
            np.testing.assert_allclose(m["bands"][0], [3.16, 5.01, 6.31, 7.94, 10.0], rtol=2e-3)
            for key, bound in BOUNDS.items():
                with self.subTest(receiver=r, measure=key):
                    self.assertLess(abs(m[key]), bound, f"{r} m: {key} {m[key]:+.4f}, "
                                    f"bands {m['bands']}")

    def test_the_scenes_block_in_metres_misses_the_16_m_band(self):
        # depth 30, margin_along 12 (147,186 DOFs): 3.59 dB at 3.16 Hz at
        # 16 m (0.90 / 0.62 dB at 4 / 8 m; at 10 elements per wavelength,
        # 89,001 DOFs: 3.59, 0.91 / 0.56 dB, depth 50 alone 2.30 dB,
        # margin_along 20 alone 1.47 dB).
        scene = whole_record(block(**SCENE_BLOCK), (16.0,))[0]
        self.assertGreater(scene[16.0]["band_db"], 2.0, scene[16.0]["bands"])
        self.assertAlmostEqual(scene[16.0]["band_at"], 3.16, delta=0.01)


class Layers(unittest.TestCase):
    """The layers' damping profile, its size and the keys (no dolfinx run)."""

    def test_profile_and_round_trip(self):
        # A block 0..30 along, 0..20 across, 10 deep; the region of interest
        # 8..22 along, to 12 across, to 4 deep: the layer's depth d/L per
        # axis, the largest of them, 0 inside.
        inner, outer = (8.0, 22.0, 12.0, -4.0), (0.0, 30.0, 20.0, -10.0)
        pts = np.array([[15.0, 5.0, -1.0], [4.0, 5.0, -1.0], [26.0, 5.0, -1.0],
                        [15.0, 16.0, -1.0], [15.0, 5.0, -7.0], [2.0, 18.0, -9.0],
                        [0.0, 20.0, -10.0], [15.0, -16.0, -1.0]])
        np.testing.assert_allclose(absorbing.profile(pts, inner, outer),
                                   [0.0, 0.5, 0.5, 0.5, 0.5, 5.0 / 6.0, 1.0, 0.5], rtol=0, atol=1e-15)
        np.testing.assert_array_equal(absorbing.thickness(pts, inner, outer)[1:6],
                                      [8.0, 8.0, 8.0, 6.0, 6.0])
        # a_max: a plane wave through the layer and back, attenuated by
        # exp(-a0 x/(2c)), comes back R times as large.
        c, L, R = 100.0, 8.0, 0.01
        a_max = absorbing.peak_damping(c, L, R)
        x = np.linspace(0.0, L, 100001)
        a0 = a_max * (x / L) ** 2
        trip = np.exp(-2.0 * np.sum(0.5 * (a0[1:] + a0[:-1]) * np.diff(x)) / (2.0 * c))
        self.assertAlmostEqual(trip, R, delta=1e-9)

    def test_keys(self):
        p = block()
        c_r = lamb.RAYLEIGH_RATIO * HALF_SPACE.shear_speed
        self.assertAlmostEqual(config.fine_depth(config.parse(
            {"layers": [{"density": 2000.0, "shear_wave_speed": 100.0, "poisson": 0.25}]})),
            2.0 * c_r / 20.0, delta=1e-9)
        # The layers' inner faces: the footprints' span, resolve_to, fine_depth.
        self.assertAlmostEqual(p.absorbing[0], 8.0, delta=1e-12)
        self.assertAlmostEqual(p.absorbing[1] - p.absorbing[0], 12.25, delta=1e-12)
        self.assertEqual(p.absorbing[2], 16.0)
        self.assertAlmostEqual(p.absorbing[3], -2.0 * c_r / 10.0, delta=1e-9)
        self.assertEqual(p.absorbing_reflection, 0.01)
        self.assertIsNone(block(growth=1.0).absorbing)  # uniform: no graded zones
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] absorbing_reflection must be <= 1"):
            block(absorbing_reflection=1.5)
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] absorbing_reflection must be > 0"):
            block(absorbing_reflection=0.0)
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] fine_depth must be >= 0"):
            block(fine_depth=-1.0)

    def test_margin_along_the_track_alone(self):
        # margin_along = 12: 12 m beyond the track's ends (the layers along
        # the track 12 m thick), the half width still the farthest receiver
        # plus margin (32 + 8); the footprints and receivers move with it.
        p, q = block(), block(margin_along=12.0)
        self.assertAlmostEqual(p.length, 12.25 + 16.0, delta=1e-12)
        self.assertAlmostEqual(q.length, 12.25 + 24.0, delta=1e-12)
        self.assertEqual((q.half_width, q.depth), (40.0, 20.0))
        self.assertAlmostEqual(q.absorbing[0], 12.0, delta=1e-12)
        self.assertAlmostEqual(q.absorbing[1], 24.25, delta=1e-12)
        self.assertEqual(q.absorbing[2:], p.absorbing[2:])
        self.assertAlmostEqual(q.footprints[0].x - p.footprints[0].x, 4.0, delta=1e-12)
        self.assertAlmostEqual(q.receivers[0][0] - 0.5 * q.length, 0.0, delta=1e-12)
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] margin_along must be > 0"):
            block(margin_along=-1.0)

    def test_a_receiver_in_the_layers_is_reported_unresolved(self):
        # The default receivers: 32 m lies beyond resolve_to (16 m), in the
        # layers; 4 to 16 m do not.
        p = block()
        cfg = config.parse({"f_max": 10.0, "growth": 1.1, "receivers": [4.0, 8.0, 16.0, 32.0],
                            "resolve_to": 16.0, "layers": [{"density": 2000.0,
                                                            "shear_wave_speed": 100.0,
                                                            "poisson": 0.25}]})
        soil = SimpleNamespace(p=p, nodes=(p.x_nodes, p.y_nodes, p.z_nodes), dt=3e-3)
        rows = resolution.resolution(soil, cfg)[1]
        self.assertEqual([f > 0.0 for _, f, _ in rows], [True, True, True, False])
        self.assertEqual(rows[3][1:], (0.0, 0.0))
        # vibration.csv's bands: in a 1 s record from the 5 Hz band (the
        # lowest 1 Hz wide or more) to the highest whose upper edge, centre
        # 10^((m + 1/2)/10), lies below the receiver's resolved frequency;
        # none at 32 m.
        bands = resolution.receiver_bands(soil, cfg, 1.0)
        for (_, f, g), (lo, hi) in zip(rows[:3], bands):
            m = math.floor(10.0 * math.log10(min(f, g)) - 0.5 + 1e-9)
            np.testing.assert_allclose((lo, hi), (10.0 ** 0.7, 10.0 ** (m / 10.0)), rtol=1e-14)
        self.assertTrue(all(map(math.isnan, bands[3])))
        text = spectrum.load_verdicts(np.ones((10, 1)), 1e-3, [16.0, 32.0],
                                      [f for _, f, _ in rows[2:]])
        self.assertIn("32 m: the receiver lies in the absorbing layers", text[1][3])
        self.assertNotIn("absorbing", text[0][3])


if __name__ == "__main__":
    unittest.main()
