#!/usr/bin/env python3
"""Runs with a soil the master cannot build into its monolithic model (the
Python soil of examples/python_soil, given with --node soil=HOST:PORT) are
judged against the product's best co-simulation of the same participants
(implicit, converged to 1e-10, at half the macro step), not against the
built-in soil's monolithic run:

- the example soil, whose physics is the built-in soil's, ends ok, its
  summary naming the co-simulation reference, its macro step, its coupling
  (cubic substep waveforms, which the example takes) and the Richardson
  estimate of the reference's own error;
- a soil four times stiffer (through its own --config) is judged against
  its own co-simulation and ends ok too (against the built-in monolithic
  run its history error is 0.69: `inaccurate` before this version);
- with --judge stability (no reference) that run's stability still holds
  the matrix-free rho, its rate and its steps, as the full judgement's do,
  under the same verdict (the section was left out where it found no
  growth);
- the same soil behind an `external` scene is judged the same way (it was
  `ok` with every error null);
- a lagged wheel-rail coupling with that soil is still caught (amplified,
  history error over 1), unstable at rest by the matrix-free growth rate
  through the participants at the dense map's rate, and --reference-step
  sets the reference's step;
- a reference whose own estimated error is over half the bound is not
  judged by (not_judged, asking for a finer --reference-step); a finer one
  judges the same run;
- a soil that gives up at every macro step shorter than 1e-4 s cannot make
  a reference: the run's status is not_judged, saying why (it was `ok`).

Usage: outside_reference_test.py SOURCE_DIR BIN_DIR
"""

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

SRC, BIN = sys.argv[1], sys.argv[2]
SOIL = os.path.join(SRC, "examples", "python_soil", "soil_participant.py")

# Gives up (StepFailed) at any macro step shorter than the scene's 1e-4 s.
SHORT_STEP_SOIL = """
import runpy
ns = runpy.run_path({soil!r})
class NoShortSteps(ns["LumpedSoil"]):
    def advance(self, t, H, inputs):
        if H < 0.99e-4:
            raise ns["rc"].StepFailed("this soil takes no macro step under 1e-4 s (H = %g s)" % H)
        return super().advance(t, H, inputs)
ns["rc"].serve(NoShortSteps())
"""


class OutsideReference(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="outside_reference_")
        cls.procs = []
        with open(os.path.join(SRC, "scenes", "soil.toml")) as f:
            text = f.read()
        # 0.02 s (200 macro steps of 1e-4 s), 10 fixed micro steps (the example
        # soil's Newmark takes a fixed count).
        text = re.sub(r"(?m)^end_time = .*$", "end_time = 0.02", text)
        # One rate (200 macro steps of the map as well): the scene's default
        # window for the soil is dropped.
        text = re.sub(r"(?m)^ss_macro_step = .*$", "", text)
        text = re.sub(r"(?m)^(tolerance = .*)$", r"\1\nmicro_steps = 10", text)
        cls.scene = cls.write("soil.toml", text)
        stiff = re.sub(r"(?m)^stiffness = 121.08e6 ", "stiffness = 484.32e6 ", text)
        assert stiff != text
        cls.stiff_config = cls.write("stiff.toml", stiff)
        cls.env = dict(os.environ, RAILCOSIM_SDK_CACHE=os.path.join(cls.work, "cache"))
        cls.same = cls.start("same", SOIL, cls.scene)
        cls.stiff = cls.start("stiff", SOIL, cls.stiff_config)
        short = cls.write("short.py", SHORT_STEP_SOIL.format(soil=SOIL))
        cls.short = cls.start("short", short, cls.scene)

    @classmethod
    def tearDownClass(cls):
        for p in cls.procs:
            p.kill()
            p.wait()
        shutil.rmtree(cls.work, ignore_errors=True)

    @classmethod
    def write(cls, name, text):
        path = os.path.join(cls.work, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    @classmethod
    def start(cls, name, program, config):
        out = os.path.join(cls.work, name + ".out")
        with open(out, "w") as f:
            p = subprocess.Popen(["/usr/bin/python3", program, "--config", config], stdout=f,
                                 stderr=subprocess.DEVNULL, env=cls.env)
        cls.procs.append(p)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            with open(out) as f:
                m = re.search(r"^listening on (\S+)$", f.read(), re.M)
            if m:
                return m.group(1)
            time.sleep(0.1)
        raise RuntimeError("the soil %s did not start within 30 s" % name)

    def run_master(self, name, case, soil, *args, scene=None):
        out = os.path.join(self.work, name)
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", scene or self.scene,
                            "--case",
                            case, "--out", out, "--node", "soil=" + soil] + list(args),
                           capture_output=True, text=True, timeout=120, env=self.env)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr[-3000:])
        with open(os.path.join(out, case, "summary.json")) as f:
            return json.load(f)

    def assert_cosim_reference(self, s, macro_step, stability="not judged"):
        ref = s["reference"]
        self.assertEqual(ref["kind"], "co-simulation", s)
        self.assertEqual(ref["macro_step_s"], macro_step, s)
        self.assertEqual(ref["coupling"], "implicit-waveform3-iqn-ils", s)
        self.assertNotIn("takes no substep waveforms", ref.get("note", ""), s)
        self.assertEqual(ref["estimate_order"], 2)
        # The reference's own error, estimated, is far below the bounds.
        self.assertLess(ref["history_error_estimate"], 1e-4, s)
        self.assertLess(ref["rel_l2_error_estimate"], 1e-4, s)
        self.assertEqual(s["stability"]["verdict"], stability, s)

    def test_same_physics_is_ok(self):
        s = self.run_master("same", "ss-xx-jacobi", self.same)
        self.assertEqual(s["status"], "ok", s)
        self.assert_cosim_reference(s, 5e-05)
        self.assertLess(s["history_error"], 0.1 * 0.1, s)
        self.assertIn("judged against the co-simulation reference", s["message"])

    def test_an_external_soil_is_judged(self):
        # The same soil behind soil.model = "external": compared with nothing
        # and called ok before (errors null); now measured as above.
        with open(self.scene) as f:
            text = f.read()
        external = self.write("external.toml", text.replace('model = "lumped"',
                                                            'model = "external"'))
        with open(external) as f:
            self.assertNotEqual(f.read(), text)
        s = self.run_master("external", "ss-xx-jacobi", self.same, scene=external)
        self.assertEqual(s["status"], "ok", s)
        self.assertIsNotNone(s["history_error"], s)
        self.assert_cosim_reference(s, 5e-05)
        self.assertLess(s["history_error"], 0.1 * 0.1, s)

    def test_different_physics_is_not_inaccurate(self):
        s = self.run_master("stiff", "ss-xx-jacobi", self.stiff)
        self.assertEqual(s["status"], "ok", s)
        self.assert_cosim_reference(s, 5e-05)
        self.assertLess(s["history_error"], 0.1 * 0.1, s)
        # Its matrix-free rho does not grow; its verdict stays not judged.
        self.assertLessEqual(s["stability"]["rho_matrix_free"], 1.0, s)
        # Ten run lengths parked (200 macro steps), at most 2000.
        self.assertEqual(s["stability"]["matrix_free_steps"], 2000, s)

    def test_stability_alone_writes_the_measured_rho(self):
        # --judge stability takes the same matrix-free measure as the full
        # judgement: its rho, rate and steps are written, and its verdict is
        # the same (stable at rest, not resolved: not judged).
        full = self.run_master("full", "ss-xx-jacobi", self.stiff)["stability"]
        s = self.run_master("stability", "ss-xx-jacobi", self.stiff, "--judge", "stability")
        self.assertEqual(s["status"], "not_judged", s)
        self.assertIn("errors not measured (--judge stability)", s["message"])
        self.assertIn("stability", s, s)
        st = s["stability"]
        self.assertEqual(st["verdict"], "not judged", s)
        self.assertEqual(st["verdict"], full["verdict"], (s, full))
        for key in ("rho_matrix_free", "rho_matrix_free_rate_per_s", "matrix_free_steps"):
            self.assertIsNotNone(st.get(key), s)
            self.assertEqual(st[key], full[key], (key, s, full))
        self.assertLessEqual(st["rho_matrix_free"], 1.0, s)
        self.assertEqual(st["matrix_free_steps"], 2000, s)

    def test_unstable_coupling_is_still_caught(self):
        s = self.run_master("lagged", "wr-xt+ss-xx-jacobi", self.stiff, "--reference-step", "2.5e-5")
        self.assertEqual(s["status"], "amplified", s)
        self.assert_cosim_reference(s, 2.5e-05, "unstable")
        self.assertGreater(s["history_error"], 1.0, s)
        # Unstable at rest, measured through the participants themselves
        # (matrix-free): the dense map of the same case with the built-in
        # soil of that stiffness, in process, has rho = 1.102, 973 /s.
        st = s["stability"]
        self.assertEqual(st["basis"], "matrix-free", s)
        self.assertAlmostEqual(st["rho_rate_per_s"], 973.0, delta=0.02 * 973.0)
        self.assertIn("measured through the participants (matrix-free", s["message"])

    def test_a_reference_too_coarse_to_judge_by_is_said_so(self):
        # A bound of 0.001 (the scene's cosim.amplification_threshold): a
        # reference (cubic waveforms) at the run's own 2e-3 s estimates its
        # error at 6.0e-4, over half of it; at 2.5e-4 s at 1.1e-4, and the
        # run (history error 0.031) is inaccurate against it.
        with open(self.scene) as f:
            text = f.read()
        tight = self.write("tight.toml", text.replace("amplification_threshold = 0.1 ",
                                                      "amplification_threshold = 0.001"))
        with open(tight) as f:
            self.assertNotEqual(f.read(), text)
        args = ("wr-xx+ss-xx-jacobi", self.stiff, "--macro-step", "2e-3")
        s = self.run_master("coarse", *args, "--reference-step", "2e-3", scene=tight)
        self.assertEqual(s["status"], "not_judged", s)
        self.assertIsNone(s["history_error"], s)
        self.assertGreater(s["reference"]["history_error_estimate"], 0.0005, s)
        self.assertIn("give a finer --reference-step", s["message"])
        s = self.run_master("fine", *args, "--reference-step", "2.5e-4", scene=tight)
        self.assertEqual(s["status"], "inaccurate", s)
        self.assertLess(s["reference"]["history_error_estimate"], 0.00025, s)
        self.assertGreater(s["history_error"], 0.01, s)

    def test_no_reference_is_not_judged(self):
        s = self.run_master("short", "ss-xx-jacobi", self.short)
        self.assertEqual(s["status"], "not_judged", s)
        self.assertIsNone(s["history_error"], s)
        self.assertEqual(s["reference"]["kind"], "none", s)
        self.assertIn("not judged: no co-simulation reference: the reference run "
                      "(implicit-waveform3-iqn-ils, H = 5e-05 s) ended failed", s["message"])
        self.assertIn("this soil takes no macro step under 1e-4 s", s["message"])


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
