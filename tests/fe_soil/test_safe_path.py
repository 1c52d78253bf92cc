"""No code from the user's working directory runs inside the FE soil: a
`numpy.py` and an `mpi4py.py` planted where the master is started (each would
leave a marker file and fail the soil if imported) change nothing; the run
ends `ok` and no marker appears. Usage: test_safe_path.py BIN_DIR"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import support  # noqa: F401  (skips without dolfinx)

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
CI_SCENE = os.path.join(SRC, "scenes", "ground_vibration_ci.toml")
CASE = "ss-xt-jacobi"
PLANTED = """import os
open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "{name}.imported"), "w").close()
raise ImportError("the planted {name}.py of the working directory was imported")
"""


class WorkingDirectory(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.work, True)
        for name in ("numpy", "mpi4py"):
            with open(os.path.join(self.work, name + ".py"), "w") as f:
                f.write(PLANTED.format(name=name))

    def test_planted_modules_are_not_imported(self):
        out = os.path.join(self.work, "out")
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", CI_SCENE, "--case",
                            CASE, "--out", out], cwd=self.work, capture_output=True, text=True,
                           timeout=200, env=dict(os.environ, OMP_NUM_THREADS="1"))
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr[-3000:])
        with open(os.path.join(out, CASE, "summary.json")) as f:
            self.assertIn('"status": "ok"', f.read())
        self.assertEqual(sorted(n for n in os.listdir(self.work) if n.endswith(".imported")), [])


if __name__ == "__main__":
    unittest.main()
