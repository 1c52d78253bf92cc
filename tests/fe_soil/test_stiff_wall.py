"""A stiff wave barrier beside a track against the measurement of
P. Coulier, V. Cuellar, G. Degrande and G. Lombaert ("Experimental and
numerical evaluation of the effectiveness of a stiff wave barrier in the
soil", Soil Dynamics and Earthquake Engineering 77 (2015) 238-253): a
jet-grout wall 7.5 m deep, 1 m wide and 55 m long beside a railway line
reduced the free-field vibration during train passages by about 5 dB from
8 Hz up, with a peak of about 12 dB near 30 Hz, immediately behind it.

scenes/jet_grout_wall.toml (that wall, 4 m from the track's centre line,
E 5 GPa, in a homogeneous soil of c_S 250 m/s: the scene's choices, not
the site's) at CI size: the mesh rule at f_max 25 Hz (the scene: 40 Hz),
receivers 6 and 12 m from the track, a Ricker force centred at 15 Hz over
0.6 s (the bands from 8 Hz judged). What is asserted is the measured
shape, not its numbers (docs/path-measures.md compares those, band by band,
at the scene's size): immediately behind the wall (6 m) the wall reduces
every judged band from 8 Hz up, by at least MIN_DB, and the reduction
grows with frequency, the highest judged band's by at least RISE_DB more
than the 8 Hz band's; farther away (12 m) the PPV's reduction is smaller.
About 60 s on one core."""
import os
import sys
import tempfile
import tomllib
import unittest

import numpy as np

from support import HALF_SPACE  # noqa: F401  (skips without dolfinx)

from fe_soil import mitigation

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "jet_grout_wall.toml")
MIN_DB = 1.5  # measured: about 5 dB from 8 Hz; here 2.3 to 7.5 dB (docs/path-measures.md)
RISE_DB = 3.0  # measured: about 5 dB at 8 Hz to 12 dB near 30 Hz; here 3.2 to 7.5 dB, 8 to 25 Hz


class StiffWall(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(SCENE, "rb") as f:
            scene = tomllib.load(f)
        scene["soil"].update(f_max=25.0, receivers=[6.0, 12.0], margin=8.0, depth=20.0)
        scene["soil"]["mitigation"].update(frequency=15.0, duration=0.6)
        cls.scene = scene
        _, losses = mitigation.study(scene, tempfile.mkdtemp(prefix="stiff_wall_"), "wall_ci")
        cls.behind, cls.farther = losses["wall"]
        fc = 10.0 ** (np.arange(len(cls.behind["band"])) / 10.0)
        cls.judged = np.isfinite(cls.behind["band"]) & (fc >= 8.0 * 0.99)
        cls.fc = fc
        print("IL behind the wall (6 m), %s Hz: %s dB; PPV %.1f dB at 6 m, %.1f dB at 12 m" % (
            np.round(fc[cls.judged], 1), np.round(cls.behind["band"][cls.judged], 1),
            cls.behind["ppv"], cls.farther["ppv"]))

    def test_the_wall_is_the_scenes(self):
        wall = self.scene["soil"]["measures"][0]
        self.assertEqual((wall["kind"], wall["depth"], wall["width"], wall["length"]),
                         ("wall", 7.5, 1.0, 55.0))

    def test_behind_it_every_band_from_8_hz_is_reduced(self):
        bands = self.behind["band"][self.judged]
        self.assertGreaterEqual(len(bands), 5)
        self.assertAlmostEqual(float(self.fc[self.judged][0]), 7.94, delta=0.01)
        self.assertGreater(float(bands.min()), MIN_DB, bands)

    def test_the_reduction_grows_with_frequency(self):
        bands = self.behind["band"][self.judged]
        self.assertGreater(float(bands[-1] - bands[0]), RISE_DB, bands)

    def test_farther_away_it_reduces_less(self):
        self.assertGreater(self.farther["ppv"], 0.0)
        self.assertLess(self.farther["ppv"], self.behind["ppv"])


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
