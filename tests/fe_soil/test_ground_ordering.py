"""The vibration on an embankment, at grade and in a cutting (fe_soil/
ground_study.py) against the ordering measured on Belgian high-speed lines
(Connolly, Alves Costa, Kouroussis, Galvin, Woodward and Laghrouche 2015,
"Large scale international testing of railway ground vibrations across
Europe", Soil Dynamics and Earthquake Engineering 71, 1-12): at equal
distances from the track, the levels beside the embankment section were
lower, and those beside the cutting higher, than at grade.

scenes/ground_shapes_ci.toml's layered soil (the ground-vibration scene's
three layers), a 2 m embankment and a 2 m cutting with 4 m wide crest and
base and 1:1.5 slopes, receivers 7 and 10 m from the centre line, a
Ricker force (15 Hz) on the middle sleeper, 0.4 s of record; the block
(3 m margins, 7 m deep) on two meshes, one per test class (argument
Coarse: 0.6 m elements, Fine: 0.5 m): the ordering must hold on both.
The bands judged are those the flat ground's mesh resolves at the
receiver within 10-80 Hz (resolution.py: 12.5 and 16 Hz on the coarse
mesh, up to 20 Hz on the fine one).

What holds, and is asserted: the embankment's summed level over the
judged bands is lower than at grade at both receivers, and so is its level
in the 16 Hz band. What does not hold and is kept as an expected failure
(docs/ground-shapes.md gives the numbers): the cutting is not higher than
at grade; the model puts it 12 to 15 dB lower."""
import math
import os
import sys
import tempfile
import tomllib
import unittest

import numpy as np

from support import HALF_SPACE  # noqa: F401  (skips without dolfinx)

from fe_soil import ground_study

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "ground_shapes_ci.toml")
MESH = {"Coarse": 0.6, "Fine": 0.5}
MARGIN_DB = 0.5  # the least difference asserted (dB)


def summed(lv, judged):
    """The judged bands' energies summed, as a level (dB)."""
    return 10.0 * math.log10(float(np.sum(10.0 ** (lv[judged] / 10.0))))


class _Ordering:
    h = None

    @classmethod
    def setUpClass(cls):
        with open(SCENE, "rb") as f:
            scene = tomllib.load(f)
        scene["soil"].update(mesh_size=cls.h, margin=3.0, depth=7.0, receivers=[7.0, 10.0])
        scene["soil"]["mitigation"]["duration"] = 0.4
        out = tempfile.mkdtemp(prefix="ground_ordering_")
        _, cls.lv, cls.diff = ground_study.study(scene, out, "ordering")
        fc = cls.lv["at_grade"][0]["fc"]
        cls.fc = fc
        cls.judged = [np.isfinite(d["band"]) & (fc >= 10.0 * 0.99) & (fc <= 80.0 * 1.01)
                      for d in cls.diff["at_grade"]]
        cls.sums = {g: [summed(p["lv"], j) for p, j in zip(per, cls.judged)]
                    for g, per in cls.lv.items()}
        print("%s (h = %g m): summed 10-80 Hz levels (dB) %s" % (cls.__name__, cls.h, cls.sums))

    def test_bands_are_judged(self):
        for j in self.judged:
            self.assertGreaterEqual(int(j.sum()), 2)

    def test_the_embankment_is_lower_than_at_grade(self):
        for k in range(2):
            self.assertLess(self.sums["embankment"][k], self.sums["at_grade"][k] - MARGIN_DB, k)
            i = int(np.argmin(abs(self.fc - 16.0)))
            self.assertTrue(self.judged[k][i])
            self.assertGreater(self.diff["embankment"][k]["band"][i], MARGIN_DB, k)

    @unittest.expectedFailure
    def test_the_cutting_is_higher_than_at_grade(self):
        for k in range(2):
            self.assertGreater(self.sums["cutting"][k], self.sums["at_grade"][k] + MARGIN_DB, k)


class Coarse(_Ordering, unittest.TestCase):
    h = MESH["Coarse"]


class Fine(_Ordering, unittest.TestCase):
    h = MESH["Fine"]


if __name__ == "__main__":
    which = sys.argv[1] if len(sys.argv) > 1 else "Coarse"
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(globals()[which])
    sys.exit(0 if unittest.TextTestRunner(verbosity=2).run(suite).wasSuccessful() else 1)
