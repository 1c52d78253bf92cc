"""`master study` on the FE soil's CI scene (scenes/ground_vibration_ci.toml,
shortened to 0.01 s): the study starts the FE soil itself, as master run
does, and gives the report every section of the paper scene's study:

- every co-simulation run of the sweep (ss-xt-jacobi's methods at 1e-4 and
  5e-4 s) is judged against the co-simulation reference of the same
  participants at the sweep's smallest macro step (implicit coupling
  converged to 1e-10), ends with a status word and says so; no monolithic
  run is planned (there is no monolithic model of the FE soil);
- the stability map carries rho for every run, each finite with its rate
  ln(rho) / H per second in summary.json;
- the speed/accuracy chart and the stability map are drawn, and the answer
  and the cheapest-method table name a run that was judged;
- the whole study stays within the budget given (--budget).

Usage: test_master_study.py BIN_DIR"""
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import support  # noqa: F401  (skips without dolfinx; puts the checkout on the path)

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
STEPS = ["1e-4", "5e-4"]
BUDGET = 600


class MasterStudyFeSoil(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="master_study_fe_")
        with open(os.path.join(SRC, "scenes", "ground_vibration_ci.toml")) as f:
            text = f.read()
        text = re.sub(r"(?m)^end_time = .*$", "end_time = 0.01", text)
        cls.scene = os.path.join(cls.work, "fe.toml")
        with open(cls.scene, "w") as f:
            f.write(text)
        cls.study = os.path.join(cls.work, "study")
        env = dict(os.environ, OMP_NUM_THREADS="1")
        start = time.monotonic()
        cls.result = subprocess.run(
            [os.path.join(BIN, "master"), "study", "--scene", cls.scene, "--out", cls.study,
             "--cases", "ss-xt-jacobi", "--macro-steps", ",".join(STEPS), "--jobs", "1",
             "--budget", str(BUDGET)], capture_output=True, text=True, timeout=BUDGET + 200,
            env=env)
        cls.seconds = time.monotonic() - start

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def runs(self):
        """(folder, method, H) of every run of the plan."""
        out = []
        with open(os.path.join(self.study, "plan.txt")) as f:
            for line in f:
                m = re.search(r" --macro-step (\S+) .* #% folder=(\S+) group=\S+ method=(\S+)",
                              line)
                if m:
                    out.append((m.group(2), m.group(3), float(m.group(1))))
        return out

    def summary(self, folder):
        with open(os.path.join(self.study, folder, "summary.json")) as f:
            return json.load(f)

    def test_study_ends_complete(self):
        self.assertEqual(self.result.returncode, 0,
                         self.result.stdout + self.result.stderr[-3000:])
        # ss-xt-jacobi lagged, resolved, implicit-linear-iqn-ils and
        # extrapolated at both steps; no monolithic run, no substep waveforms.
        methods = sorted({m for _, m, _ in self.runs()})
        self.assertEqual(methods, ["ss-xt-jacobi", "ss-xt-jacobi+explicit-extrapolate1",
                                   "ss-xt-jacobi+implicit-linear-iqn-ils",
                                   "ss-xt-jacobi-resolved"])
        self.assertEqual(len(self.runs()), 8)
        self.assertLess(self.seconds, BUDGET)

    def test_every_run_is_judged_against_its_own_reference(self):
        for folder, method, H in self.runs():
            s = self.summary(folder)
            self.assertEqual(s["reference"]["kind"], "co-simulation", (folder, s))
            self.assertEqual(s["reference"]["macro_step_s"], 1e-4, (folder, s))
            self.assertEqual(s["reference"]["coupling"], "implicit-linear-iqn-ils", folder)
            self.assertIn(s["status"], ("ok", "inaccurate", "amplified"), (folder, s["message"]))
            self.assertIn("judged against the co-simulation reference", s["message"], folder)
            self.assertTrue(math.isfinite(s["rel_l2_error"]), folder)

    def test_every_run_carries_rho_and_its_rate(self):
        for folder, method, H in self.runs():
            st = self.summary(folder)["stability"]
            rho = st["rho"] if st["rho"] is not None else st.get("rho_matrix_free")
            self.assertIsNotNone(rho, (folder, st))
            self.assertTrue(0 < rho < 10, (folder, st))
            rate = st["rho_rate_per_s"] if st["rho"] is not None else st["rho_matrix_free_rate_per_s"]
            self.assertAlmostEqual(rate, math.log(rho) / H, delta=1e-9 * abs(rate) + 1e-9,
                                   msg=(folder, st))

    def test_report_has_the_map_and_the_chart(self):
        with open(os.path.join(self.study, "REPORT.md")) as f:
            report = f.read()
        for section in ("**The answer.**", "## Stability map", "## Cheapest method per accuracy",
                        "## Largest stable macro step per method", "## Every run",
                        "judged, and charted, against the co-simulation reference"):
            self.assertIn(section, report)
        for figure in ("speed_accuracy", "stability_map"):
            self.assertGreater(os.path.getsize(os.path.join(self.study, "figures",
                                                            figure + ".png")), 0)
        stability_map = report.split("## Stability map")[1].split("\n## ")[0]
        for method in {m for _, m, _ in self.runs()}:
            row = re.search(r"(?m)^\| %s \| (.*)$" % re.escape(method), stability_map).group(1)
            self.assertEqual(len(re.findall(r"ρ [0-9.]+", row)), len(STEPS), row)
        # The chart's points are the runs' errors against their reference.
        with open(os.path.join(self.study, "front.csv"), newline="") as f:
            front = [r for r in csv.DictReader(f) if r["method"]]
        self.assertTrue(front)
        for r in front:
            s = self.summary(r["folder"])
            self.assertEqual(s["reference"]["kind"], "co-simulation", r)
            self.assertAlmostEqual(float(r["error"]), s["rel_l2_error"], delta=1e-12)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
