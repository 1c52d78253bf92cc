#!/usr/bin/env python3
"""An OSError from a Python participant's own code is not a lost
connection: the SDK's server sends the master an Error naming the
participant and the reason, and the master's message carries it (before,
the master read "the peer closed the connection"). And the Green's-function
soil whose cache folder cannot be written still runs `ok`, warning that it
computed without caching. Usage: participant_oserror_test.py BIN_DIR SOURCE_DIR"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else None
SRC = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..")
BIN = BIN or os.path.join(SRC, "build", "bin")

FAILING = """import runpy, sys
ns = runpy.run_path(%r)
class FailsToWrite(ns["LumpedSoil"]):
    def advance(self, t, H, inputs):
        if t >= 3 * H:
            raise PermissionError(13, "Permission denied", "/results/soil_log.csv")
        return super().advance(t, H, inputs)
ns["rc"].serve(FailsToWrite())
"""


class ParticipantOSError(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp()
        self.env = dict(os.environ, RAILCOSIM_SDK_CACHE=os.path.join(self.work, "sdk-cache"),
                        OMP_NUM_THREADS="1")
        self.procs = []

    def tearDown(self):
        for p, out in self.procs:
            p.kill()
            p.wait()
            out.close()
        shutil.rmtree(self.work, ignore_errors=True)

    def start(self, program, *args):
        out = open(os.path.join(self.work, "node.out"), "w+")
        p = subprocess.Popen(["/usr/bin/python3", program] + list(args), stdout=out,
                             stderr=subprocess.DEVNULL, env=self.env)
        self.procs.append((p, out))
        deadline = time.monotonic() + 40
        while time.monotonic() < deadline:
            out.seek(0)
            m = re.search(r"^listening on (\S+)", out.read(), re.M)
            if m:
                return m.group(1)
            time.sleep(0.05)
        self.fail("the participant did not start")

    def test_participant_oserror_reaches_the_master(self):
        with open(os.path.join(SRC, "scenes", "soil.toml")) as f:
            text = f.read()
        text = re.sub(r"(?m)^end_time = .*", "end_time = 0.005", text)
        text = re.sub(r"(?m)^ss_macro_step.*\n", "", text)
        text, n = re.subn(r"(?m)^(tolerance = .*)$", r"\1\nmicro_steps = 10", text)
        self.assertEqual(n, 1)
        scene = os.path.join(self.work, "soil.toml")
        with open(scene, "w") as f:
            f.write(text)
        program = os.path.join(self.work, "fails.py")
        with open(program, "w") as f:
            f.write(FAILING % os.path.join(SRC, "examples", "python_soil", "soil_participant.py"))
        address = self.start(program, "--config", scene)
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", scene, "--case",
                            "wr-xx+ss-xx-jacobi", "--node", "soil=" + address, "--out",
                            os.path.join(self.work, "out")], capture_output=True, text=True,
                           timeout=120, env=self.env)
        log = p.stdout + p.stderr
        self.assertNotEqual(p.returncode, 0, log)
        self.assertIn("the soil participant failed: PermissionError: [Errno 13] Permission denied:"
                      " '/results/soil_log.csv'", log)
        self.assertNotIn("closed the connection", log)

    def test_green_soil_with_an_unwritable_cache_runs_ok(self):
        blocker = os.path.join(self.work, "not-a-folder")
        open(blocker, "w").close()
        env = dict(self.env, XDG_CACHE_HOME=os.path.join(blocker, "cache"))
        out = os.path.join(self.work, "green")
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene",
                            os.path.join(SRC, "scenes", "ground_vibration_green_ci.toml"),
                            "--case", "ss-xt-jacobi", "--out", out, "--verbose"],
                           capture_output=True, text=True, timeout=300, env=env)
        log = p.stdout + p.stderr
        self.assertEqual(p.returncode, 0, log[-3000:])
        with open(os.path.join(out, "ss-xt-jacobi", "summary.json")) as f:
            self.assertEqual(json.load(f)["status"], "ok")
        self.assertIn("computed without caching, which costs only time", log)


if __name__ == "__main__":
    try:
        import numpy  # noqa: F401
    except ImportError as e:  # pragma: no cover
        print("SKIP: numpy is not importable (%s)" % e)
        sys.exit(77)
    unittest.main()
