"""The FE soil's mesh keys are bounded before anything is meshed: a master
run whose scene asks for an element size the machine cannot hold, for
thousands of receivers or for more MPI ranks than the machine can hold,
fails within seconds naming the scene file, the key and the bound (it grew
past 2.3 GiB and ended in a MemoryError naming nothing, or served the
receivers for minutes), and `master run --check` refuses the same scene
with the same reason. Usage: test_limits.py BIN_DIR"""
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
        logs = []
        for check in (["--check"], []):  # a check that passes would start the ranks
            start = time.monotonic()
            p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", scene, "--case",
                                "ss-xt-jacobi", "--out", os.path.join(self.work, "out")] + check,
                               capture_output=True, text=True, timeout=120,
                               env=dict(os.environ, OMP_NUM_THREADS="1"))
            log = p.stdout + p.stderr
            self.assertNotEqual(p.returncode, 0, " ".join(check) + ": " + log[-2000:])
            self.assertIn(expected, log)
            self.assertIn(scene + ": [soil] ", log)  # the file and the key
            self.assertNotIn("check: would run", log)
            self.assertLess(time.monotonic() - start, 60)
            logs.append(log)
        return "\n".join(logs)

    def test_an_element_size_the_machine_cannot_hold(self):
        log = self.refused("mesh_size = 1.0 ", "mesh_size = 0.05 ", "[soil] mesh_size = 0.05 m gives ")
        self.assertIn("DOFs (at most 2000000, and half its", log)

    def test_elements_too_many_to_list(self):
        self.refused("mesh_size = 1.0 ", "mesh_size = 1e-6 ",
                     "elements along the block of ")

    def test_more_ranks_than_the_machine_holds(self):
        with open(CI_SCENE) as f:
            self.assertIn("\nranks = ", f.read())
        self.refused("\nranks = ", "\nranks = 256 #", "[soil] ranks = 256 starts 256 processes")

    def test_the_ci_scene_passes_the_check(self):
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--check", "--scene", CI_SCENE,
                            "--case", "ss-xt-jacobi"], capture_output=True, text=True, timeout=120)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("check: would run ss-xt-jacobi", p.stdout)

    def test_thousands_of_receivers(self):
        self.refused("receivers = [2.0, 4.0]",
                     "receivers = [%s]" % ", ".join("%g" % (1 + 0.001 * k) for k in range(5000)),
                     "[soil] receivers lists 5000 distances; at most 64")


if __name__ == "__main__":
    unittest.main()
