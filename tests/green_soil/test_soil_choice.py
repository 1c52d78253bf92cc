"""green_soil.study on scenes/ground_vibration_green_ci.toml: which soil
the scene needs. REPORT.md has the section; its differences per receiver
and band, soil_choice.csv and soil_choice.json are recomputed here from the
per-soil records each run wrote (runs/*/vibration.csv); a record changed
after the study (a planted mismatch) fails that recomputation; the chart is
a PNG image; the study's one-way check passed; the FE scene it runs holds
the same layers and receivers. With python3-dolfinx the study runs the FE
soil too (--fe, a 1 m mesh 6 m deep): its mesh resolves 12.0 Hz (10
elements per Rayleigh wavelength of the top layer), so every band of the
0.02 s record (50 and 100 Hz) is compared with the Green's-function soil,
and the FE rows show the mesh's difference from it. Usage:
test_soil_choice.py BIN_DIR"""
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import tomllib
import unittest

import support  # skips without scipy; puts the checkout on the path

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
SCENE = os.path.join(SRC, "scenes", "ground_vibration_green_ci.toml")
DISTANCES = [2.0, 4.0, 8.0]
FE_KEYS = "mesh_size = 1.0, depth = 6.0, margin = 2.0"


def has_dolfinx():
    p = subprocess.run(["/usr/bin/python3", "-c", "import dolfinx"], capture_output=True)
    return p.returncode == 0


def records(out, summary):
    """{soil key: {distance: {column: float}}} read from each run's vibration.csv."""
    got = {}
    for s in summary["soils"]:
        with open(os.path.join(out, s["folder"], "vibration.csv"), newline="") as f:
            got[s["key"]] = {float(r["y_m"]): {k: float(v) for k, v in r.items() if k != "receiver"}
                             for r in csv.DictReader(f)}
    return got


def verify(out):
    """Recomputes the comparison from the records; raises AssertionError on
    the first number of soil_choice.csv, soil_choice.json or REPORT.md that
    does not follow from them."""
    with open(os.path.join(out, "soil_choice.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "REPORT.md")) as f:
        report = f.read()
    rec = records(out, summary)
    col = {f: "Lv_z_%gHz_dB" % f for f in summary["bands_Hz"]}
    resolved = dict(zip(summary["receivers_m"], summary.get("reference_resolved_Hz", [])))

    def ref_key(d, band):  # the most complete run, up to the band its mesh resolves
        trusted = band <= resolved.get(d, math.inf)
        return summary["reference"] if trusted else summary["reference_above"]

    with open(os.path.join(out, "soil_choice.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(rec) * len(summary["receivers_m"]) * len(col), len(rows)
    diffs = {k: [] for k in rec}
    for r in rows:
        d, band = float(r["receiver_m"]), float(r["band_Hz"])
        assert r["reference"] == ref_key(d, band), r
        level, base = rec[r["soil"]][d][col[band]], rec[ref_key(d, band)][d][col[band]]
        for shown, exact in ((r["level_dB"], level), (r["reference_dB"], base),
                             (r["difference_dB"], level - base)):
            assert abs(float(shown) - exact) <= 1e-6, (r, exact)
        diffs[r["soil"]].append(level - base)
    for s in summary["soils"]:
        dd = diffs[s["key"]]
        assert abs(s["max_abs_difference_dB"] - max(abs(x) for x in dd)) <= 1e-9, s
        rms = math.sqrt(sum(x * x for x in dd) / len(dd))
        assert abs(s["rms_difference_dB"] - rms) <= 1e-9, s
    labels = {s["label"]: s for s in summary["soils"]}
    for cells in support.report_rows(report, "### Cost and largest difference"):
        s = labels[cells[0]]
        assert abs(float(cells[4]) - s["max_abs_difference_dB"]) <= 0.0051, cells
        assert abs(float(cells[5]) - s["rms_difference_dB"]) <= 0.0051, cells
    keys = [s["key"] for s in summary["soils"]]
    for d in summary["receivers_m"]:
        table = support.report_rows(report, "### %g m: level minus" % d)
        assert len(table) == len(col), (d, table)
        for cells, band in zip(table, summary["bands_Hz"]):
            ref = rec[ref_key(d, band)][d]
            assert abs(float(cells[0]) / band - 1) <= 0.01, (cells, band)
            assert cells[1] == labels_by_key(summary)[ref_key(d, band)], (d, cells)
            assert abs(float(cells[2]) - ref[col[band]]) <= 0.0051, (d, cells)
            for shown, k in zip(cells[3:], keys):
                exact = rec[k][d][col[band]] - ref[col[band]]
                assert abs(float(shown) - exact) <= 0.0051, (d, band, k, shown, exact)
    return summary


def labels_by_key(summary):
    return {s["key"]: s["label"] for s in summary["soils"]}


class SoilChoice(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="soil_choice_")
        cls.out = os.path.join(cls.work, "study")
        env = dict(os.environ, OMP_NUM_THREADS="1", XDG_CACHE_HOME=cls.work)
        cls.fe = has_dolfinx()
        p = subprocess.run(["/usr/bin/python3", "-m", "green_soil.study", "--scene", SCENE,
                            "--out", cls.out, "--master", os.path.join(BIN, "master")]
                           + (["--fe", FE_KEYS] if cls.fe else []),
                           cwd=SRC, capture_output=True, text=True, timeout=230, env=env)
        assert p.returncode == 0, p.stdout + p.stderr[-3000:]
        with open(os.path.join(cls.out, "REPORT.md")) as f:
            cls.report = f.read()
        with open(os.path.join(cls.out, "soil_choice.json")) as f:
            cls.summary = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def test_section_and_soils(self):
        for s in ["## Which soil a scene needs", "### Cost and largest difference",
                  "### 2 m: level minus", "### 4 m: level minus", "### 8 m: level minus",
                  "## Validation", "### Checks run by this study",
                  "### The Green's-function soil's tests", "## Figures"]:
            self.assertIn("\n" + s, self.report)
        if not self.fe:
            self.assertEqual([s["key"] for s in self.summary["soils"]], ["lumped", "green"])
            self.assertEqual(self.summary["reference"], "green")  # no FE run without --fe
            return
        self.assertEqual([s["key"] for s in self.summary["soils"]], ["lumped", "green", "fe"])
        self.assertEqual(self.summary["reference"], "fe")
        self.assertEqual(self.summary["reference_above"], "green")
        # c_R of the top layer (128 m/s, nu = 0.375) over 10 elements of 1 m.
        for f in self.summary["reference_resolved_Hz"]:
            self.assertAlmostEqual(f, 12.015, delta=1e-3)
        self.assertIn("12 Hz at 2 m", self.report)
        self.assertEqual(self.summary["receivers_m"], DISTANCES)
        # 0.02 s holds no band below 50 Hz; the centres are 10^(n/10) Hz
        self.assertEqual(len(self.summary["bands_Hz"]), 2)
        for got, band in zip(self.summary["bands_Hz"], (17, 20)):
            self.assertAlmostEqual(got, 10 ** (band / 10), delta=1e-4)

    def test_resolved_bands_per_receiver(self):
        # 0.02 s: spectral lines 50 Hz apart, wider than any band to 100 Hz
        # (the 100 Hz band is 23 Hz wide): no band is resolved at any receiver.
        rows = support.report_rows(self.report, "## Levels at the receivers")
        self.assertEqual([float(r[0].split()[0]) for r in rows], DISTANCES)
        for r in rows:
            self.assertEqual(r[3], "none", r)
            self.assertEqual(r[4], "the 0.02 s record / the taper from 120 Hz (0.8 f_max)", r)
        self.assertEqual(self.summary["green_resolved_Hz"], [[None, None]] * len(DISTANCES))

    def test_numbers_follow_from_the_records(self):
        summary = verify(self.out)
        ref = next(s for s in summary["soils"] if s["key"] == "green")
        self.assertEqual(ref["max_abs_difference_dB"], 0.0)
        lumped = next(s for s in summary["soils"] if s["key"] == "lumped")
        self.assertGreater(lumped["max_abs_difference_dB"], 0.0)  # two different runs
        if self.fe:  # a 1 m mesh at 50 and 100 Hz: far from the ground's levels
            fe = next(s for s in summary["soils"] if s["key"] == "fe")
            self.assertGreater(fe["max_abs_difference_dB"], 3.0)

    def test_a_planted_mismatch_fails(self):
        copy = os.path.join(self.work, "planted")
        shutil.copytree(self.out, copy)
        path = os.path.join(copy, "runs", "two-step", "vibration.csv")
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        k = rows[0].index("Lv_z_100Hz_dB")
        rows[2][k] = "%.9g" % (float(rows[2][k]) + 0.02)  # 4 m, 100 Hz: 0.02 dB more
        with open(path, "w", newline="") as f:
            csv.writer(f, lineterminator="\n").writerows(rows)
        with self.assertRaises(AssertionError):
            verify(copy)

    def test_cost(self):
        rows = {r[0]: r for r in support.report_rows(self.report, "### Cost and largest difference")}
        self.assertEqual(sorted(rows), ["FE", "Green's functions", "lumped (two-step)"][
            0 if self.fe else 1:])
        for s in self.summary["soils"]:
            self.assertGreater(s["wall_s"], 0.0)
            self.assertGreater(s["cpu_s"], 0.0)
            self.assertAlmostEqual(s["wall_s"], sum(s["parts"].values()), delta=1e-9)
            self.assertAlmostEqual(float(rows[s["label"]][2]), s["wall_s"], delta=0.0051)
            self.assertAlmostEqual(float(rows[s["label"]][3]), s["cpu_s"], delta=0.0051)
        self.assertEqual(len(self.summary["soils"][0]["parts"]), 3)  # Green's, lumped, one way

    def test_chart_and_check(self):
        path = os.path.join(self.out, "figures", "soil_choice.png")
        with open(path, "rb") as f:
            head = f.read(24)
        self.assertEqual(head[:8], b"\x89PNG\r\n\x1a\n")
        w, h = struct.unpack(">II", head[16:24])
        self.assertGreater(w * h, 100000)
        self.assertGreater(os.path.getsize(path), 10000)
        check = support.report_rows(self.report, "### Checks run by this study")
        self.assertEqual(len(check), 1)
        self.assertEqual(check[0][-1], "pass", check)
        tests = [r[0] for r in support.report_rows(self.report, "### The Green's-function soil's tests")]
        for name in ("lamb", "static", "causality", "convergence", "participant", "cosim",
                     "radial", "soil_choice"):
            self.assertIn("`green_soil_%s`" % name, tests)

    def test_the_fe_scene_has_the_same_ground(self):
        from fe_soil import config as fe_config
        from green_soil import config as green_config
        from green_soil import study

        with open(SCENE, "rb") as f:
            scene = tomllib.load(f)
        path = study.scene_with_soil(SCENE, study.fe_table(scene, {"mesh_size": 1.0,
                                                                   "depth": 6.0}),
                                     os.path.join(self.work, "fe.toml"))
        with open(path, "rb") as f:
            fe_scene = tomllib.load(f)
        fe = fe_config.parse(fe_scene["soil"])
        green = green_config.parse(scene["soil"])
        self.assertEqual(fe["receivers"], green["receivers"])
        self.assertEqual(fe["layers"][:-1], green["layers"][:-1])
        self.assertEqual(fe_scene["soil"]["mesh_size"], 1.0)
        self.assertEqual(fe_scene["vehicle"], scene["vehicle"])
        self.assertTrue(fe_scene["output"]["ballast_forces"])

    def test_refuses_an_fe_scene(self):
        p = subprocess.run(["/usr/bin/python3", "-m", "green_soil.study", "--scene",
                            os.path.join(SRC, "scenes", "ground_vibration_ci.toml"), "--out",
                            os.path.join(self.work, "x"), "--master", os.path.join(BIN, "master")],
                           cwd=SRC, capture_output=True, text=True, timeout=60)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn('[soil] model must be "green"', p.stderr)
        self.assertIn("fe_soil.study", p.stderr)


if __name__ == "__main__":
    unittest.main()
