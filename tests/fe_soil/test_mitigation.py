"""The insertion-loss study (fe_soil/mitigation.py) on
scenes/ground_vibration_trench_ci.toml, its record shortened to 0.3 s
(the bands from 16 Hz up judged), with a second measure added that is no
measure at all: an in-fill of the top layer's own material. The
reference variant equals a plain run of the scene's soil (its table with
variant = "reference", as `master run` builds it), built and driven here
on its own, to 1e-12 of each receiver's peak over the whole record; the
null measure's record equals the reference's to 1e-12 and its insertion
loss is zero, which only holds because the variants share one mesh (on a
mesh of its own the reference moved by 1.4e-3 of the peak at 3 m);
insertion_loss.csv holds the differences of the runs' measures read back
from their records (PPV and KB_Fmax of the records low-passed at the
frequency the mesh resolves at each receiver); REPORT.md names the receivers where the trench
amplifies, and the figure is written."""
import csv
import math
import os
import sys
import tempfile
import tomllib
import unittest

import numpy as np

from support import HALF_SPACE  # noqa: F401  (skips without dolfinx)

from fe_soil import config, measures, mitigation
from fe_soil.model import FESoil

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "scenes",
                     "ground_vibration_trench_ci.toml")


def plain_record(scene, load):
    """The scene's FE soil as a plain run builds it (variant "reference":
    no measure built, their faces in the mesh), under the Ricker force on
    the middle footprint."""
    cfg = config.parse(dict(scene["soil"], variant="reference"))
    fps = mitigation.footprints(scene, load["sleepers"])
    soil = FESoil(config.block_params(cfg, fps)[0])
    fc, H, n = load["frequency"], load["step"], load["sleepers"]
    t0 = 1.2 / fc
    f = [np.zeros(n), np.zeros(n)]
    for k in range(int(round(load["duration"] / H))):
        for j, t in enumerate((k * H, (k + 1) * H)):
            a = (math.pi * fc * (t - t0)) ** 2
            f[j][n // 2] = load["amplitude"] * (1.0 - 2.0 * a) * math.exp(-a)
        soil.advance(k * H, H, f[0], f[1])
    return soil.receiver_series()


class Mitigation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(SCENE, "rb") as f:
            cls.scene = tomllib.load(f)
        cls.scene["soil"]["mitigation"]["duration"] = 0.3
        top = cls.scene["soil"]["layers"][0]
        cls.scene["soil"]["measures"].append(dict(
            {k: top[k] for k in ("density", "shear_wave_speed", "poisson", "damping")},
            name="null", kind="infilled_trench", distance=7.0, depth=1.0, width=1.0,
            length=6.0))
        cls.load = mitigation.load_keys(cls.scene["soil"]["mitigation"])
        cls.out = tempfile.mkdtemp(prefix="mitigation_")
        cls.records, cls.losses = mitigation.study(cls.scene, cls.out, "trench_ci")

    def test_the_reference_equals_the_plain_run(self):
        t, v = plain_record(self.scene, self.load)
        ref = self.records["reference"]
        self.assertEqual(ref.shape, v.shape)
        for k in range(v.shape[1]):
            scale = np.abs(v[:, k, :]).max()
            self.assertGreater(scale, 0.0)
            err = float(np.abs(ref[:, k, :] - v[:, k, :]).max() / scale)
            self.assertLess(err, 1e-12, "receiver %d" % k)
        saved = np.load(os.path.join(self.out, "runs", "reference", "receivers.npz"))
        np.testing.assert_array_equal(saved["v"], ref)
        np.testing.assert_array_equal(saved["t"], t)

    def test_a_measure_of_the_soils_own_material_changes_nothing(self):
        ref, null = self.records["reference"], self.records["null"]
        for k in range(ref.shape[1]):
            scale = np.abs(ref[:, k, :]).max()
            self.assertLess(float(np.abs(null[:, k, :] - ref[:, k, :]).max() / scale), 1e-12, k)
        for il in self.losses["null"]:
            self.assertLess(float(np.nanmax(np.abs(il["band"]))), 1e-9)
            for q in ("ppv", "kb_fmax", "overall"):
                self.assertLess(abs(il[q]), 1e-9, q)

    def test_the_table_is_the_difference_of_the_records(self):
        with open(os.path.join(self.out, "insertion_loss.csv")) as f:
            rows = [r for r in csv.DictReader(f) if r["measure"] == "trench"]
        dt = self.load["step"]
        ref, var = self.records["reference"], self.records["trench"]
        names = ["r3m", "r6m", "r9m"]
        self.assertEqual(sorted({r["receiver"] for r in rows}), names)
        for k, name in enumerate(names):
            got = {r["quantity"]: float(r["IL_dB"]) for r in rows
                   if r["receiver"] == name and r["quantity"] != "band"}
            # PPV and KB_Fmax of the records low-passed at the resolved frequency
            top = self.losses["trench"][k]["lowpass_hz"]
            self.assertGreater(top, 16.0)  # above the judged 16 Hz band, below 40 Hz
            self.assertLess(top, 40.0)
            r_lp, m_lp = (measures.low_passed(x[:, k, 2], dt, top) for x in (ref, var))
            want = 20.0 * math.log10(measures.ppv(r_lp) / measures.ppv(m_lp))
            self.assertAlmostEqual(got["ppv"], want, delta=1e-4)
            want = 20.0 * math.log10(measures.kb_fmax(r_lp, dt) / measures.kb_fmax(m_lp, dt))
            self.assertAlmostEqual(got["kb_fmax"], want, delta=1e-4)
            fc, lr = measures.third_octave_levels(ref[:, k, 2], dt, 1.0, 80.0)
            _, lm = measures.third_octave_levels(var[:, k, 2], dt, 1.0, 80.0)
            judged = [r for r in rows if r["receiver"] == name and r["quantity"] == "band"
                      and r["IL_dB"]]
            self.assertGreater(len(judged), 0)
            for r in judged:
                i = int(np.argmin(abs(fc - float(r["band_hz"]))))
                self.assertAlmostEqual(float(r["IL_dB"]), lr[i] - lm[i], delta=1e-4)
        # behind the trench (6 and 9 m) its PPV is lower than the reference's
        self.assertTrue(all(il["ppv"] > 0.0 for il in self.losses["trench"][1:]))

    def test_the_report_names_where_it_amplifies(self):
        with open(os.path.join(self.out, "REPORT.md")) as f:
            text = f.read()
        self.assertIn("## trench: trench", text)
        per = self.losses["trench"]
        for name, il in zip(["r3m", "r6m", "r9m"], per):
            negative = il["ppv"] < 0.0 or bool(np.any(il["band"][np.isfinite(il["band"])] < 0.0))
            self.assertEqual(negative, name + " (" in text, name)
        self.assertGreater(os.path.getsize(os.path.join(self.out, "figures",
                                                        "insertion_loss.png")), 10000)

    def test_keys_of_the_load_are_refused_by_name(self):
        for table, pattern in (({"sleeper": 3}, r"\[soil\] mitigation\.sleeper is not a key"),
                               ({"sleepers": 2.5}, r"\[soil\] mitigation\.sleepers must be a whole"),
                               ({"step": 0.0}, r"\[soil\] mitigation\.step must be > 1e-05 \(got 0\)"),
                               ({"frequency": -1.0}, r"\[soil\] mitigation\.frequency must be > 0\.1"),
                               ({"step": 1e-30}, r"\[soil\] mitigation\.step must be > 1e-05"),
                               ({"duration": 0.01}, r"\[soil\] mitigation\.duration 0\.01 s holds")):
            with self.assertRaisesRegex(config.ConfigError, pattern):
                mitigation.load_keys(table)
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] measures: the scene lists none"):
            scene = dict(self.scene, soil={k: v for k, v in self.scene["soil"].items()
                                           if k not in ("measures", "variant")})
            mitigation.study(scene, self.out)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
