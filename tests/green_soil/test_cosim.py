"""The Green's-function soil in real co-simulations: `master run` on
scenes/ground_vibration_green_ci.toml starts it itself (ss-xt-jacobi,
explicit; and implicit coupling, which saves and restores it), writes its
measures beside the run's files; --transport inproc is refused naming tcp.
Usage: test_cosim.py BIN_DIR"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import support  # noqa: F401  (skips without scipy; puts the checkout on the path)

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
SCENE = os.path.join(SRC, "scenes", "ground_vibration_green_ci.toml")
CASE = "ss-xt-jacobi"


def table(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


class CoSimulation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp()
        # The Green's functions are cached in the test's own folder.
        cls.env = dict(os.environ, OMP_NUM_THREADS="1", XDG_CACHE_HOME=cls.work)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def run_master(self, out, *args, status=0):
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", SCENE, "--case", CASE,
                            "--out", os.path.join(self.work, out), "--verbose"] + list(args),
                           capture_output=True, text=True, timeout=240, env=self.env)
        self.assertEqual(p.returncode, status, p.stdout + p.stderr[-3000:])
        return os.path.join(self.work, out, CASE), p.stdout + p.stderr

    def assert_ok(self, folder, method):
        with open(os.path.join(folder, "summary.json")) as f:
            summary = f.read()
        self.assertIn('"status": "ok"', summary)
        self.assertIn('"method": "%s"' % method, summary)
        head, rows = table(os.path.join(folder, "history.csv"))
        self.assertEqual(head[-3:], ["r2m_vz_mps", "r4m_vz_mps", "r8m_vz_mps"])
        hist = np.array([[float(x) for x in r] for r in rows])
        self.assertEqual(hist.shape[0], 201)
        self.assertTrue(np.isfinite(hist).all())
        head, rows = table(os.path.join(folder, "vibration.csv"))
        self.assertEqual([r[0] for r in rows], ["r2m_vz_mps", "r4m_vz_mps", "r8m_vz_mps"])
        ppv = [float(r[head.index("ppv_z_mps")]) for r in rows]
        self.assertTrue(ppv[0] > ppv[1] > ppv[2] > 0.0, ppv)  # the nearer, the stronger
        return hist

    def test_explicit_and_implicit_runs(self):
        folder, log = self.run_master("explicit")
        self.assertIn("started the Green's-function soil", log)
        explicit = self.assert_ok(folder, "explicit")
        folder, _ = self.run_master("implicit", "--coupling", "implicit")
        implicit = self.assert_ok(folder, "implicit")
        # Implicit coupling converges each step where the explicit Jacobi
        # scheme lags a step: the receivers agree to a few per cent of their peak.
        peak = np.abs(implicit[:, -3]).max()
        self.assertLess(np.abs(explicit[:, -3] - implicit[:, -3]).max(), 0.1 * peak)

    def test_inproc_is_refused(self):
        _, log = self.run_master("inproc", "--transport", "inproc", status=2)
        self.assertIn("the Green's-function soil (soil.model = \"green\")", log)
        self.assertIn("--transport tcp", log)


if __name__ == "__main__":
    unittest.main()
