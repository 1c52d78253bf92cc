"""The ground shapes' comparison (fe_soil/ground_study.py, python3 -m
fe_soil.mitigation --grounds) on scenes/ground_shapes_ci.toml: the flat
ground's run, and a run of a listed ground of shape "at_grade", each
equal to a plain run of the scene's soil without any ground key, built
and driven here on its own, to 1e-12 of each receiver's peak over the
whole record of every receiver and component; ground_levels.csv holds
the levels and differences read back from the records; the report names
each ground and the figure is written."""
import csv
import math
import os
import sys
import tempfile
import tomllib
import unittest

import numpy as np

from support import HALF_SPACE  # noqa: F401  (skips without dolfinx)

from fe_soil import config, ground_study, measures, mitigation
from fe_soil.model import FESoil

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "ground_shapes_ci.toml")


def plain_record(scene, load):
    """The scene's FE soil with its ground keys taken out of the table."""
    table = {k: v for k, v in scene["soil"].items() if k not in ("grounds", "ground")}
    cfg = config.parse(table)
    soil = FESoil(config.block_params(cfg, mitigation.footprints(scene, load["sleepers"]))[0])
    fc, H, n = load["frequency"], load["step"], load["sleepers"]
    t0 = 1.2 / fc
    f = [np.zeros(n), np.zeros(n)]
    for k in range(int(round(load["duration"] / H))):
        for j, t in enumerate((k * H, (k + 1) * H)):
            a = (math.pi * fc * (t - t0)) ** 2
            f[j][n // 2] = load["amplitude"] * (1.0 - 2.0 * a) * math.exp(-a)
        soil.advance(k * H, H, f[0], f[1])
    return soil.receiver_series()


def close(test, a, b):
    test.assertEqual(a.shape, b.shape)
    for k in range(b.shape[1]):
        scale = np.abs(b[:, k, :]).max()
        test.assertGreater(scale, 0.0)
        test.assertLess(float(np.abs(a[:, k, :] - b[:, k, :]).max() / scale), 1e-12, k)


class GroundStudy(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(SCENE, "rb") as f:
            cls.scene = tomllib.load(f)
        cls.scene["soil"]["mitigation"]["duration"] = 0.3
        # a listed ground of shape at_grade: the same as the flat ground
        cls.scene["soil"]["grounds"].append({"name": "flat", "shape": "at_grade"})
        cls.load = mitigation.load_keys(cls.scene["soil"]["mitigation"])
        cls.out = tempfile.mkdtemp(prefix="ground_study_")
        cls.records, cls.levels, cls.diff = ground_study.study(cls.scene, cls.out, "shapes_ci")
        cls.plain = plain_record(cls.scene, cls.load)

    def test_at_grade_equals_the_plain_run(self):
        t, v = self.plain
        close(self, self.records["at_grade"], v)
        close(self, self.records["flat"], v)
        saved = np.load(os.path.join(self.out, "runs", "at_grade", "receivers.npz"))
        np.testing.assert_array_equal(saved["v"], self.records["at_grade"])
        np.testing.assert_array_equal(saved["t"], t)
        np.testing.assert_array_equal(saved["z"], 0.0)

    def test_the_table_holds_the_records_levels(self):
        with open(os.path.join(self.out, "ground_levels.csv")) as f:
            rows = list(csv.DictReader(f))
        dt = self.load["step"]
        self.assertEqual(sorted({r["ground"] for r in rows}),
                         ["at_grade", "cutting", "embankment", "flat"])
        for g in ("embankment", "cutting"):
            for k, name in enumerate(["r8m", "r12m"]):
                mine = {r["quantity"]: r for r in rows
                        if r["ground"] == g and r["receiver"] == name}
                # PPV of the records low-passed at the flat ground's resolved frequency
                top = self.diff[g][k]["lowpass_hz"]
                self.assertGreater(top, 0.0)
                vz, vr = (measures.low_passed(self.records[x][:, k, 2], dt, top)
                          for x in (g, "at_grade"))
                self.assertAlmostEqual(float(mine["ppv_mps"]["value"]), measures.ppv(vz),
                                       delta=1e-6 * measures.ppv(vz))
                self.assertAlmostEqual(float(mine["ppv_mps"]["difference_dB"]),
                                       20.0 * math.log10(measures.ppv(vr) / measures.ppv(vz)),
                                       delta=1e-4)
                # the band levels of the records as they are (judged where resolved)
                fc, lv = measures.third_octave_levels(self.records[g][:, k, 2], dt, 1.0, 80.0)
                _, lr = measures.third_octave_levels(self.records["at_grade"][:, k, 2], dt,
                                                     1.0, 80.0)
                bands = [r for r in rows if r["ground"] == g and r["receiver"] == name
                         and r["quantity"] == "band_dB"]
                self.assertEqual(len(bands), len(fc))
                for r in bands:
                    i = int(np.argmin(abs(fc - float(r["band_hz"]))))
                    if r["value"]:
                        self.assertAlmostEqual(float(r["value"]), lv[i], delta=1e-4)
                    if r["difference_dB"]:
                        self.assertAlmostEqual(float(r["difference_dB"]), lr[i] - lv[i], delta=1e-4)
        flat = [float(r["difference_dB"]) for r in rows if r["ground"] == "flat"
                and r["difference_dB"]]
        self.assertTrue(flat and all(x == 0.0 for x in flat))

    def test_the_report_names_each_ground(self):
        with open(os.path.join(self.out, "REPORT.md")) as f:
            text = f.read()
        for head in ("## at_grade: at grade", "## embankment: embankment", "## cutting: cutting"):
            self.assertIn(head, text)
        self.assertGreater(os.path.getsize(os.path.join(self.out, "figures",
                                                        "ground_difference.png")), 10000)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
