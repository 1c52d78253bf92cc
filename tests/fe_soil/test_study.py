"""fe_soil.study on scenes/ground_vibration_ci.toml: REPORT.md has each
section, its numbers are those of each run's vibration.csv (read back), its
two-way minus two-step table is the difference of those files, its decay
exponents follow from them, the figures are PNG images, and the checks it
ran passed. Usage: test_study.py BIN_DIR"""
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

import support  # noqa: F401  (skips without dolfinx; puts the checkout on the path)

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from report_table import report_rows as section  # noqa: E402

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
CI_SCENE = os.path.join(SRC, "scenes", "ground_vibration_ci.toml")
# method label in the report -> its folder under runs/
FOLDERS = {"Jacobi": "jacobi/ss-xt-jacobi", "Gauss-Seidel": "gauss-seidel/ss-xt-gauss-seidel",
           "implicit": "implicit/ss-xt-jacobi", "two-step": "two-step"}
SECTIONS = ["## Answer", "### Free field per distance", "### One-third-octave levels of v_z",
            "### Two-way minus two-step (dB)", "#### 2 m", "#### 4 m", "### Cost",
            "## Decay with distance", "## Figures", "## Validation",
            "### Checks run by this study", "### The FE soil's tests"]


# The soil's cut at its own window, 5 H (multirate): the study runs its
# co-simulations at it.
WINDOW = 5e-4
WINDOW_TABLE = "\n[coupling]\nss_macro_step = 5e-4\n"


def scene_copy(work, name, extra):
    """The CI scene with `extra` appended, in work/name."""
    with open(CI_SCENE) as f:
        text = f.read()
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text + extra)
    return path


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">II", head[16:24])


class Study(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp()
        cls.out = os.path.join(cls.work, "study")
        cls.scene = scene_copy(cls.work, "windowed.toml", WINDOW_TABLE)
        env = dict(os.environ, OMP_NUM_THREADS="1")
        p = subprocess.run(["/usr/bin/python3", "-m", "fe_soil.study", "--scene", cls.scene,
                            "--out", cls.out, "--master", os.path.join(BIN, "master")],
                           cwd=SRC, capture_output=True, text=True, timeout=200, env=env)
        assert p.returncode == 0, p.stdout + p.stderr[-3000:]
        with open(os.path.join(cls.out, "REPORT.md")) as f:
            cls.report = f.read()
        cls.vib = {}
        for label, folder in FOLDERS.items():
            with open(os.path.join(cls.out, "runs", folder, "vibration.csv"), newline="") as f:
                cls.vib[label] = {r["y_m"]: {k: (v if k == "receiver" else float(v))
                                             for k, v in r.items()} for r in csv.DictReader(f)}

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def row(self, label, distance):
        return self.vib[label]["%.9g" % float(distance.rstrip(" m"))]

    def test_sections(self):
        for s in SECTIONS:
            self.assertIn("\n" + s, self.report)

    def test_free_field_is_each_runs_vibration_csv(self):
        rows = section(self.report, "### Free field per distance")
        self.assertEqual(len(rows), 2 * len(FOLDERS))
        for d, label, ppv, ppv_z, kb, kb_z in rows:
            r = self.row(label, d)
            for shown, exact in ((ppv, r["ppv_mps"]), (ppv_z, r["ppv_z_mps"]),
                                 (kb, max(r["kb_fmax_x"], r["kb_fmax_y"], r["kb_fmax_z"])),
                                 (kb_z, r["kb_fmax_z"])):
                self.assertGreater(exact, 0.0)
                # 4 significant digits: within 5e-4 relative
                self.assertAlmostEqual(float(shown) / exact, 1.0, delta=5e-4, msg=(d, label))

    def bands(self):
        """The vertical band columns finite in every run."""
        cols = [c for c in self.vib["implicit"]["2"] if c.startswith("Lv_z_")]
        return [c for c in cols if all(math.isfinite(r[c]) for v in self.vib.values()
                                       for r in v.values())]

    def test_levels_and_the_difference_table(self):
        cols = self.bands()
        self.assertTrue(cols)  # 0.02 s holds the 50 and 100 Hz bands
        rows = section(self.report, "### One-third-octave levels of v_z")
        self.assertEqual(len(rows), len(cols))
        for cells, c in zip(rows, cols):
            self.assertAlmostEqual(float(cells[0]), float(c[5:-5]), delta=0.01 * float(c[5:-5]))
            for shown, d in zip(cells[1:], ("2", "4")):
                self.assertAlmostEqual(float(shown), self.vib["implicit"][d][c], delta=0.0051)
        for d in ("2", "4"):
            rows = section(self.report, "#### %s m" % d)
            self.assertEqual(len(rows), len(cols))
            for cells, c in zip(rows, cols):
                base = self.vib["two-step"][d][c]
                self.assertAlmostEqual(float(cells[1]), base, delta=0.0051)
                for shown, label in zip(cells[2:], ("Jacobi", "Gauss-Seidel", "implicit")):
                    self.assertAlmostEqual(float(shown), self.vib[label][d][c] - base,
                                           delta=0.0051, msg=(d, c, label))
                # 0.02 s: lines 50 Hz apart, no band resolved (vibration.csv: nan)
                self.assertTrue(math.isnan(self.vib["implicit"][d]["resolved_to_hz"]))
                self.assertEqual(cells[5], "no", (d, c))
        self.assertIn("Resolved at each receiver (its vibration.csv's resolved_from_hz to "
                      "resolved_to_hz, band centres): 2 m: none; 4 m: none.", self.report)
        self.assertIn("over the bands resolved: none resolved at 2 m, none resolved at 4 m; "
                      "over every band: ", self.report)

    def test_decay_exponents(self):
        rows = section(self.report, "## Decay with distance")
        self.assertEqual([r[0] for r in rows], ["2 m", "4 m"])
        p = [self.vib["implicit"][d]["ppv_z_mps"] for d in ("2", "4")]
        kb = [self.vib["implicit"][d]["kb_fmax_z"] for d in ("2", "4")]
        self.assertAlmostEqual(float(rows[1][3]), -math.log(p[1] / p[0]) / math.log(2.0),
                               delta=0.0051)
        self.assertAlmostEqual(float(rows[1][5]), -math.log(kb[1] / kb[0]) / math.log(2.0),
                               delta=0.0051)
        self.assertAlmostEqual(float(rows[1][2]), p[1] / p[0], delta=0.00051)

    def test_cost(self):
        rows = {r[0]: r for r in section(self.report, "### Cost")}
        self.assertEqual(sorted(rows), sorted(FOLDERS))
        for r in rows.values():
            self.assertGreater(float(r[2]), 0.0)
        with open(os.path.join(self.out, "runs", FOLDERS["implicit"], "summary.json")) as f:
            it = json.load(f)["iterations"]
        self.assertEqual(rows["implicit"][4], "%s mean, %s max" % (it["mean"], it["max"]))
        self.assertGreater(it["mean"], 1.0)

    def test_checks_passed(self):
        rows = section(self.report, "### Checks run by this study")
        self.assertEqual(len(rows), 4)
        for r in rows:
            self.assertEqual(r[-1], "pass", r)

    def test_the_fe_soils_tests_are_the_validation_pages_table(self):
        # Not a note that the page is missing: it is beside the package.
        rows = section(self.report, "### The FE soil's tests")
        names = {r[0] for r in rows}
        for name in ("statics", "whole_record", "whole_record_full", "damping_law", "cosim"):
            self.assertIn("`fe_soil_%s`" % name, names)
        self.assertNotIn("is not beside this package", self.report)

    def test_figures_and_snapshots(self):
        figs = [x.split("`")[1] for x in self.report.split("## Figures")[1].split("\n## ")[0]
                .splitlines() if x.startswith("- `")]
        self.assertEqual(len(figs), 4)
        for name in figs:
            path = os.path.join(self.out, name)
            w, h = png_size(path)
            self.assertGreater(w * h, 10000, name)
            self.assertGreater(os.path.getsize(path), 5000, name)
        two = os.path.join(self.out, "runs", "two-step")
        with open(os.path.join(two, "velocity.xdmf")) as f:
            xdmf = f.read()
        self.assertEqual(xdmf.count('<Time Value="'), 6)  # --snapshots default
        self.assertGreater(os.path.getsize(os.path.join(two, "velocity.h5")), 0)

    def test_the_cosimulations_ran_the_soil_at_its_window(self):
        self.assertIn("\nWindows: H = 0.0001 s; in the co-simulations ss at 0.0005 s (5 H)",
                      self.report)
        cost = {r[0]: r for r in section(self.report, "### Cost")}
        for label, folder in FOLDERS.items():
            if label == "two-step":
                continue
            self.assertIn("--macro-step ss=0.0005`", cost[label][1])
            with open(os.path.join(self.out, "runs", folder, "receivers.csv"), newline="") as f:
                t = [float(r["t_s"]) for r in csv.DictReader(f)]
            # the FE soil's own record: a row per window of the soil
            self.assertEqual(len(t), round(0.02 / WINDOW), (label, t[:3]))
            for a, b in zip(t, t[1:]):
                self.assertAlmostEqual(b - a, WINDOW, delta=1e-12, msg=label)

    def test_refuses_a_coupling_table_with_other_keys(self):
        scene = scene_copy(self.work, "implicit.toml",
                           "\n[coupling]\nss_macro_step = 5e-4\nimplicit = true\n")
        p = subprocess.run(["/usr/bin/python3", "-m", "fe_soil.study", "--scene", scene, "--out",
                            os.path.join(self.work, "y"), "--master", os.path.join(BIN, "master")],
                           cwd=SRC, capture_output=True, text=True, timeout=60)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn(scene + ": the scene has a [coupling] table, which sets how master run "
                      "couples one case", p.stderr)
        self.assertIn("(implicit)", p.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.work, "y", "runs")))

    def test_refuses_a_lumped_scene(self):
        p = subprocess.run(["/usr/bin/python3", "-m", "fe_soil.study", "--scene",
                            os.path.join(SRC, "scenes", "soil.toml"), "--out",
                            os.path.join(self.work, "x"), "--master", os.path.join(BIN, "master")],
                           cwd=SRC, capture_output=True, text=True, timeout=60)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn('[soil] model must be "fe"', p.stderr)
        self.assertIn("master study", p.stderr)


class ResolvedBands(unittest.TestCase):
    """The report's resolved bands and its largest difference over them,
    on rows made here: 4 m resolves 1-20 Hz, 8 m 5-20 Hz, 32 m none."""

    def test_largest_difference_over_the_resolved_bands(self):
        from fe_soil import study_report

        nan = math.nan
        # the band centres 10^(m/10) of m = 0, 7, 13, 14; the file's rows
        # hold them to 9 digits
        bs = [("Lv_z_%gHz_dB" % f, f) for f in (10.0 ** (m / 10.0) for m in (0, 7, 13, 14))]

        def row(lo, hi, levels):
            r = {"resolved_from_hz": lo, "resolved_to_hz": hi}
            r.update({c: v for (c, _), v in zip(bs, levels)})
            return r

        levels = [60, 70, 80, 90]
        ref = [row(1.0, 19.9526231, levels), row(5.01187234, 19.9526231, levels),
               row(nan, nan, levels)]
        two = [row(nan, nan, [61, 70.5, 80.25, 95]), row(nan, nan, [63, 70.5, 80.25, 95]),
               row(nan, nan, [61, 70, 80, 90])]
        runs = {"implicit": {"vibration": ref}, "two-step": {"vibration": two}}
        d = [4.0, 8.0, 32.0]
        self.assertEqual(study_report.worst_text(runs, bs, d, True),
                         "1.00 dB at 4 m, 0.50 dB at 8 m, none resolved at 32 m")
        self.assertEqual(study_report.worst_text(runs, bs, d, False),
                         "5.00 dB at 4 m, 5.00 dB at 8 m, 1.00 dB at 32 m")
        self.assertEqual([study_report.resolved(ref[1], f) for _, f in bs],
                         [False, True, True, False])
        self.assertEqual([study_report.span(r) for r in ref], ["1-20 Hz", "5.01-20 Hz", "none"])
        self.assertFalse(study_report.resolved(ref[1], 10.0 ** 0.6))  # 3.98 Hz

    def test_receivers_in_the_absorbing_layers_are_named(self):
        from fe_soil import study_report

        info = {"distances": [4.0, 16.0, 32.0],
                "resolution": (120.0, [(0.5, 24.0, 47.5), (0.5, 24.0, 31.2), (2.48, 0.0, 0.0)])}
        self.assertEqual(study_report.damped(info), [
            "", "32 m: inside the absorbing layers, which damp it: its PPV, KB_Fmax, levels and "
            "decay exponent are the layers', not the ground's (raise [soil] resolve_to beyond it "
            "to measure there)."])
        info["resolution"][1][1] = (2.0, 0.0, 0.0)
        self.assertIn("16 m, 32 m: inside the absorbing layers, which damp them: their PPV",
                      study_report.damped(info)[1])
        info["resolution"] = (120.0, info["resolution"][1][:1])
        info["distances"] = [4.0]
        self.assertEqual(study_report.damped(info), [])


if __name__ == "__main__":
    unittest.main()
