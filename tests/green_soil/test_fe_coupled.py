"""The Green's-function soil against the FE soil in the same coupled run:
`master run` (ss-xt-jacobi, two-way, the soil started by the master) of a
wheel at 18 km/h on scenes/soil.toml's track (30 sleepers, H = 5e-4 s,
0.2 s: the wheel moves 1 m), once on each soil, on the same elastic
homogeneous ground (c_S = 150 m/s, nu = 1/3). Compared from the runs'
files: every sleeper's ballast force over the whole record
(soil_forces.csv), the wheel's displacement over the whole record
(history.csv), the rail's deflection and every footprint's displacement
at t_end (deflection.csv, soil.csv).

The ground is elastic in both: the Green's soil's hysteretic loss creeps
(its ramp response at 0.2 s is 1.083 of the elastic static value at
xi = 0.03), the FE soil's Rayleigh damping does not, so a damped ground
is not the same ground in the two models (measured at xi = 0.03: the
footprints 12 % of their peak apart, the wheel 3.0 %). The FE block
keeps its default static far field (static_reach 5): with its springs
alone (static_reach 0) its footprints' static displacements run from
0.50 to 1.26 of the far field's along this short block, and the
comparison below is further apart (the wheel 1.2 %, the footprints 6.5 %).

Measured (elastic): ballast forces within 0.15 % of their peak, the
wheel's displacement within 0.77 %, the rail's deflection 0.80 %, the
footprints 2.7 % of their peak (the FE soil's footprints with their own
compliance, `footprint_compliance`; the FE alone: 0.70 %, 0.79 %, 0.74 %,
3.4 %). What remains: the FE block's far field,
solved for the load's first position and held while the wheel moves (the
FE soil's footprints at t_end are 0.91 to 1.06 of its own static state
with the wheel there; the Green's soil's are 0.99 to 1.04 of that static
state), and, for the FE alone, the FE mesh's footprint (h = 0.5 m, about
one element along it; statics with one footprint loaded: the FE block's
own displacement 0.866 of the Green's soil's, its neighbours' 1.07 and 1.06, so the load
spread over the sleepers under a wheel comes out 1.04 of the FE's; all
footprints loaded alike: 0.985). The comparison does not resolve a
footprint's own flexibility finer than that: the Green's soil's own
footprint spring made 1.25 times stiffer stays within the bounds (0.30 %,
1.10 %, 4.2 %); green_soil_participant checks it against the closed form
to 1 %. Seen
failing: the Green's soil's shear modulus doubled (green_soil/spectral.py's
moduli; all three bounds: 1.6 %, 13 %, 48 %), and 1.1 or 0.9 times (the
wheel, 1.8 % and 3.8 %, and the footprints, 6.6 % and 15 %); its own
footprint spring 0.8 times (1.7 %, 3.1 %, 13 %); the ground damped, xi =
0.03 in both (the wheel 3.0 %, the footprints 12 %).

Usage: test_fe_coupled.py BIN_DIR"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import support  # noqa: F401  (skips without scipy; puts the checkout on the path)

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import soil_scene_text  # noqa: E402

try:
    import dolfinx  # noqa: F401
except ImportError as e:  # pragma: no cover
    print(f"SKIP: dolfinx is not importable ({e}); "
          "scripts/install-deps.sh --fe installs python3-dolfinx")
    sys.exit(77)

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
CASE = "ss-xt-jacobi"

# The bounds, relative to the FE run's peak of each quantity (measured
# values in the module's text and docs/ground-vibration-validation.md).
BALLAST = 0.012
WHEEL = 0.015
RAIL = 0.015
FOOTPRINTS = 0.06

GROUND = """receivers = [2.0]
[[soil.layers]]
density = 1800.0
shear_wave_speed = 150.0
poisson = 0.3333333333333333
damping = 0.0

"""
SOILS = {"fe": '[soil]\nmodel = "fe"\nmesh_size = 0.5\ndepth = 6.0\nmargin = 3.0\n' + GROUND,
         "green": '[soil]\nmodel = "green"\nmemory = 0.2\n' + GROUND}


def table(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return np.array([[float(x) for x in r] for r in rows[1:]])


def scene_text(model):
    """scenes/soil.toml at 18 km/h on 30 sleepers for 0.2 s, its lumped soil
    replaced by `model`'s [soil] table."""
    text = soil_scene_text.wheel_at_18_kmh()
    return text.replace(text[text.index("[soil]"):text.index("[output]")], SOILS[model])


def largest(a, b):
    """max |a - b| relative to max |a|."""
    return float(np.abs(a - b).max() / np.abs(a).max())


class FeCoupled(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="green_fe_coupled-")
        # The Green's functions are cached in the test's own folder.
        env = dict(os.environ, OMP_NUM_THREADS="1", XDG_CACHE_HOME=cls.work)
        cls.runs = {}
        for model in SOILS:
            scene = os.path.join(cls.work, model + ".toml")
            with open(scene, "w") as f:
                f.write(scene_text(model))
            out = os.path.join(cls.work, model)
            p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", scene, "--case",
                                CASE, "--out", out], capture_output=True, text=True,
                               timeout=80, env=env)
            if p.returncode != 0:
                raise AssertionError("the %s soil's run failed (%d):\n%s" % (
                    model, p.returncode, p.stdout + p.stderr[-3000:]))
            cls.runs[model] = os.path.join(out, CASE)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def both(self, name):
        return [table(os.path.join(self.runs[m], name)) for m in ("fe", "green")]

    def test_runs_are_whole(self):
        for model, folder in self.runs.items():
            with open(os.path.join(folder, "summary.json")) as f:
                self.assertIn('"status": "ok"', f.read(), model)
        fe, green = self.both("soil_forces.csv")
        self.assertEqual(fe.shape, (401, 31))
        self.assertEqual(green.shape, fe.shape)
        self.assertTrue(np.array_equal(fe[:, 0], green[:, 0]))

    def test_ballast_forces(self):
        """Every sleeper's ballast force over the whole record (the static
        state at t = 0 included): measured 0.69 % of the peak (38.8 kN)."""
        fe, green = self.both("soil_forces.csv")
        self.assertGreater(np.abs(fe[:, 1:]).max(), 3e4)
        self.assertLess(largest(fe[:, 1:], green[:, 1:]), BALLAST)

    def test_wheel_and_rail(self):
        """The wheel's displacement over the whole record (2.64 mm, of which
        0.77 mm is the soil's): measured 0.79 %; the rail's deflection at
        t_end: 0.74 %."""
        fe, green = self.both("history.csv")
        self.assertLess(largest(fe[:, 1], green[:, 1]), WHEEL)
        fe, green = self.both("deflection.csv")
        self.assertTrue(np.array_equal(fe[:, 0], green[:, 0]))
        self.assertLess(largest(fe[:, 1], green[:, 1]), RAIL)

    def test_footprints(self):
        """Every footprint's displacement at t_end: measured 3.4 % of the
        peak (0.77 mm); the soil's share of the wheel's displacement."""
        fe, green = self.both("soil.csv")
        self.assertEqual(fe.shape, (30, 2))
        self.assertTrue(np.array_equal(fe[:, 0], green[:, 0]))
        self.assertGreater(fe[:, 1].max(), 5e-4)
        self.assertLess(largest(fe[:, 1], green[:, 1]), FOOTPRINTS)


if __name__ == "__main__":
    unittest.main()
