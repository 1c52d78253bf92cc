#!/usr/bin/env python3
"""A Python-SDK participant whose static solve takes longer than the
master's reply limit (RAILCOSIM_REPLY_SECONDS, set short here): the example
soil of examples/python_soil, whose first Statics takes 6 s or more. While its
static_iterations count advances, the SDK sends progress frames with step -1
and the run ends `ok`; a soil that stays silent is named with "static
state" and the reply limit; one whose count stops is named "no progress";
one that keeps advancing past the statics budget (10 x the step budget) is
stopped there; one whose frames carry another step than -1 (macro step 0)
is refused at the first, a bad reply naming the soil, the step and -1. The
C++ SDK the same: a track node (tests/broken_node slow-statics) whose
statics() calls work_progress() for 4 s.
Usage: python_statics_progress_test.py BIN_DIR SOURCE_DIR"""
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
import railcosim_sdk.session
from soil_participant import LumpedSoil

# The step the SDK puts in a Statics' progress frames (-1 unless the test
# plants another).
railcosim_sdk.session.STATICS_STEP = %(statics_step)d

class SlowStatics(LumpedSoil):
    first = True

    def statics(self, inputs):
        if self.first:
            self.first = False
            start = time.monotonic()
            while time.monotonic() < start + %(seconds)r:
                time.sleep(0.05)
                if time.monotonic() < start + %(advancing)r:
                    self.static_iterations += 1
        return super().statics(inputs)

rc.serve(SlowStatics())
'''

REPLY_SECONDS = 3


class StaticsProgress(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp(prefix="python_statics_progress_")
        self.addCleanup(shutil.rmtree, self.work, True)
        with open(os.path.join(SRC, "scenes", "soil.toml")) as f:
            text = f.read()
        text = re.sub(r"\nend_time = [^\n]*", "\nend_time = 0.004", text)
        text = re.sub(r"\nss_macro_step = [^\n]*", "", text)
        text = re.sub(r"\n(tolerance = [^\n]*)", "\n\\1\nmicro_steps = 10", text)
        self.scene = os.path.join(self.work, "soil.toml")
        with open(self.scene, "w") as f:
            f.write(text)

    def start_node(self, argv):
        """Starts a node that prints its address first; returns HOST:PORT.
        It is killed and waited for when the test ends."""
        node = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        self.addCleanup(node.stdout.close)
        self.addCleanup(node.wait)
        self.addCleanup(node.kill)
        return node.stdout.readline().split()[-1]

    def run_case(self, seconds, advancing, *flags, statics_step=-1):
        """The run with a soil whose first statics takes `seconds`, its
        count advancing for the first `advancing` of them, its progress
        frames carrying `statics_step`."""
        script = os.path.join(self.work, "soil.py")
        with open(script, "w") as f:
            f.write(SOIL % {"example": os.path.join(SRC, "examples", "python_soil"),
                            "sdk": os.path.join(SRC, "sdk", "python"), "seconds": seconds,
                            "advancing": advancing, "statics_step": statics_step})
        address = self.start_node(["/usr/bin/python3", script, "--config", self.scene])
        out = os.path.join(self.work, "out")
        env = dict(os.environ, RAILCOSIM_REPLY_SECONDS=str(REPLY_SECONDS))
        start = time.monotonic()
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", self.scene, "--case",
                            "ss-xx-jacobi", "--node", "soil=" + address, "--out", out, *flags],
                           capture_output=True, text=True, timeout=60, env=env)
        seconds = time.monotonic() - start
        with open(os.path.join(out, "ss-xx-jacobi", "summary.json")) as f:
            summary = json.load(f)
        return p, summary, seconds, address

    def failed(self, p, summary, address):
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        self.assertEqual(summary["status"], "failed")
        message = summary["message"]
        self.assertIn("soil node at " + address + ": static state: ", message)
        self.assertIn("before the run", message)
        return message

    def test_a_long_static_solve_showing_progress_ends_ok(self):
        p, summary, seconds, _ = self.run_case(6.0, 6.0)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertEqual(summary["status"], "ok", summary["message"])
        self.assertGreater(seconds, 6.0)  # the long statics was waited for

    def test_a_silent_static_solve_is_named_at_the_reply_limit(self):
        p, summary, seconds, address = self.run_case(6.0, 0.0)
        message = self.failed(p, summary, address)
        self.assertIn("no reply within 3000 ms", message)
        self.assertIn("RAILCOSIM_REPLY_SECONDS", message)
        self.assertLess(seconds, 6.0)

    def test_a_static_solve_whose_progress_stops_is_named(self):
        p, summary, seconds, address = self.run_case(8.0, 1.0)
        message = self.failed(p, summary, address)
        self.assertIn("no progress for 3000 ms (its last progress frame that counted was at "
                      "count ", message)
        self.assertLess(seconds, 8.0)

    def test_a_static_solve_past_its_budget_is_stopped(self):
        # --step-budget 0.5 s: the statics budget is 10 times that, 5 s.
        p, summary, seconds, address = self.run_case(10.0, 10.0, "--step-budget", "0.5")
        message = self.failed(p, summary, address)
        self.assertIn("static state: budget of 5 s exhausted", message)
        self.assertIn("--step-budget", message)
        self.assertLess(seconds, 10.0)

    def test_a_progress_frame_for_another_step_is_refused(self):
        # Frames for macro step 0 while the Statics works: the first one
        # ends the run, long before the 2 s solve would.
        p, summary, seconds, address = self.run_case(2.0, 2.0, statics_step=0)
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        self.assertEqual(summary["status"], "failed")
        self.assertIn("soil node at " + address + ": bad reply: a progress frame for macro step 0 "
                      "during the static state (expected step -1) before the run", summary["message"])
        self.assertLess(seconds, 2.0)

    def test_a_cpp_node_static_solve_showing_progress_ends_ok(self):
        with open(os.path.join(SRC, "scenes", "paper.toml")) as f:
            text = re.sub(r"\nend_time = [^\n]*", "\nend_time = 0.004", f.read())
        scene = os.path.join(self.work, "paper.toml")
        with open(scene, "w") as f:
            f.write(text)
        address = self.start_node([os.path.join(BIN, "broken_node"), "slow-statics", "--listen",
                                   "127.0.0.1:0", "--role", "track"])
        out = os.path.join(self.work, "out")
        env = dict(os.environ, RAILCOSIM_REPLY_SECONDS=str(REPLY_SECONDS))
        start = time.monotonic()
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", scene, "--case",
                            "wr-xx-jacobi", "--node", "track=" + address, "--out", out],
                           capture_output=True, text=True, timeout=60, env=env)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertGreater(time.monotonic() - start, 4.0)


if __name__ == "__main__":
    unittest.main()
