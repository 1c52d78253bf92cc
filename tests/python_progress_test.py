#!/usr/bin/env python3
"""A Python-SDK participant's macro step that legitimately takes long,
against one that is stuck: the example soil of examples/python_soil, whose
macro step 300 takes 4 s (the steps before it about a millisecond, so the
master's step deadline is its floor of 2 s). In `slow` mode its micro-step
count advances while it works, and the SDK sends progress frames
(Configure.progress_ms): the run ends `ok` on both data planes. In `stuck`
mode the count stays: the SDK sends nothing, and the master names the soil
within seconds. Usage: python_progress_test.py BIN_DIR SOURCE_DIR"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

BIN, SRC = os.path.abspath(sys.argv.pop(1)), os.path.abspath(sys.argv.pop(1))

SOIL = '''
import sys, time
sys.path.insert(0, %(example)r)
sys.path.insert(0, %(sdk)r)
import railcosim_sdk as rc
from soil_participant import LumpedSoil

class Slow(LumpedSoil):
    def advance(self, t, H, inputs):
        if round(t / H) == 300:
            end = time.monotonic() + 4.0
            while time.monotonic() < end:
                time.sleep(0.05)
                if %(advancing)r:
                    self.micro_steps += 1
        return super().advance(t, H, inputs)

rc.serve(Slow())
'''


class Progress(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp(prefix="python_progress_")
        self.addCleanup(shutil.rmtree, self.work, True)
        with open(os.path.join(SRC, "scenes", "soil.toml")) as f:
            text = f.read()
        text = re.sub(r"\nend_time = [^\n]*", "\nend_time = 0.04", text)
        # One rate: the soil is stuck at a given macro step of its own.
        text = re.sub(r"\nss_macro_step = [^\n]*", "", text)
        text = re.sub(r"\n(tolerance = [^\n]*)", "\n\\1\nmicro_steps = 10", text)
        self.scene = os.path.join(self.work, "soil.toml")
        with open(self.scene, "w") as f:
            f.write(text)

    def run_case(self, advancing, plane):
        script = os.path.join(self.work, "soil.py")
        with open(script, "w") as f:
            f.write(SOIL % {"example": os.path.join(SRC, "examples", "python_soil"),
                            "sdk": os.path.join(SRC, "sdk", "python"), "advancing": advancing})
        soil = subprocess.Popen(["/usr/bin/python3", script, "--config", self.scene],
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        self.addCleanup(soil.stdout.close)
        self.addCleanup(soil.wait)
        self.addCleanup(soil.kill)
        address = soil.stdout.readline().split()[-1]
        out = os.path.join(self.work, "out")
        start = time.monotonic()
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", self.scene, "--case",
                            "ss-xx-jacobi", "--node", "soil=" + address, "--data-plane", plane,
                            "--out", out], capture_output=True, text=True, timeout=120)
        with open(os.path.join(out, "ss-xx-jacobi", "summary.json")) as f:
            summary = json.load(f)
        return p, summary, time.monotonic() - start, address

    def slow(self, plane):
        p, summary, seconds, _ = self.run_case(True, plane)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertEqual(summary["status"], "ok", summary["message"])
        self.assertGreater(seconds, 4.0)  # the long step was taken

    def stuck(self, plane):
        p, summary, seconds, address = self.run_case(False, plane)
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        self.assertEqual(summary["status"], "failed")
        self.assertIn("soil node at " + address, summary["message"])
        self.assertIn("no reply within", summary["message"])
        self.assertLess(seconds, 10.0)

    def test_a_long_step_showing_progress_ends_ok_relayed(self):
        self.slow("relay")

    def test_a_long_step_showing_progress_ends_ok_direct(self):
        self.slow("direct")

    def test_a_stuck_step_is_named_relayed(self):
        self.stuck("relay")


if __name__ == "__main__":
    unittest.main()
