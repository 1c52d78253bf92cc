"""The FE soil's mesh keys are bounded before anything is meshed: a master
run whose scene asks for an element size the machine cannot hold, or for
thousands of receivers, fails within seconds naming the scene file, the key
and the bound (it grew past 2.3 GiB and ended in a MemoryError naming
nothing, or served the receivers for minutes). Usage: test_limits.py BIN_DIR"""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import support  # noqa: F401  (skips without dolfinx)

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
CI_SCENE = os.path.join(SRC, "scenes", "ground_vibration_ci.toml")


class Limits(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.work, True)

    def refused(self, old, new, expected):
        with open(CI_SCENE) as f:
            text = f.read()
        self.assertIn(old, text)
        scene = os.path.join(self.work, "scene.toml")
        with open(scene, "w") as f:
            f.write(text.replace(old, new))
        start = time.monotonic()
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", scene, "--case",
                            "ss-xt-jacobi", "--out", os.path.join(self.work, "out")],
                           capture_output=True, text=True, timeout=120,
                           env=dict(os.environ, OMP_NUM_THREADS="1"))
        self.assertNotEqual(p.returncode, 0, p.stdout + p.stderr[-2000:])
        self.assertIn(expected, p.stdout + p.stderr)
        self.assertIn(scene + ": [soil] ", p.stdout + p.stderr)  # the file and the key
        self.assertLess(time.monotonic() - start, 60)
        return p.stdout + p.stderr

    def test_an_element_size_the_machine_cannot_hold(self):
        log = self.refused("mesh_size = 1.0 ", "mesh_size = 0.05 ", "[soil] mesh_size = 0.05 m gives ")
        self.assertIn("DOFs (at most 2000000, and half its", log)

    def test_elements_too_many_to_list(self):
        self.refused("mesh_size = 1.0 ", "mesh_size = 1e-6 ",
                     "elements along the block (")

    def test_thousands_of_receivers(self):
        self.refused("receivers = [2.0, 4.0]",
                     "receivers = [%s]" % ", ".join("%g" % (1 + 0.001 * k) for k in range(5000)),
                     "[soil] receivers lists 5000 distances; at most 64")


if __name__ == "__main__":
    unittest.main()
