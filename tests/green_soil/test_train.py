"""scenes/ground_vibration_train.toml, the AVE S-103 trainset at 300 km/h on
the layered ground of Lincent through the Green's-function soil: the
scene's train as its sources give it (8 cars, 200.32 m, 15.5 t per axle),
and the scene as a user studies it (python3 -m green_soil.study, what
scripts/run-main.sh runs on it), cut to 0.1 s and two receivers
(tests/soil_scene_text.py). The study runs the soil at the scene's own
window ([coupling] ss_macro_step) in the two-way run and in its one-way
check; the track is the auto rule's around the whole train (its count
worked out here from the cars' geometry); the report states the bands
resolved at each receiver. Usage: test_train.py BIN_DIR"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
import unittest

import support  # skips without scipy; puts the checkout on the path

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import soil_scene_text  # noqa: E402

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
SCENE = os.path.join(SRC, "scenes", "ground_vibration_train.toml")


def cars(scene):
    """The scene's cars front to back, each table repeated `count` times."""
    out = []
    for c in scene["vehicle"]["cars"]:
        out += [c] * c.get("count", 1)
    return out


def auto_count(scene, wheel_span):
    """The auto rule's sleepers (common/scene.cpp, Scene::size_track)."""
    r, s, p, b = scene["rail"], scene["sleepers"], scene["railpad"], scene["ballast"]
    support_ = p["stiffness"] * b["stiffness"] / (p["stiffness"] + b["stiffness"])
    beta = (support_ / s["spacing"] / (4.0 * r["young_modulus"] * r["second_moment"])) ** 0.25
    margin = math.log(1e4) / beta
    x0, l = scene["vehicle"]["initial_position"], s["spacing"]
    v_t = scene["vehicle"]["speed_kmh"] / 3.6 * scene["simulation"]["end_time"]
    start = l * math.floor((x0 - wheel_span - margin) / l)
    return round((l * math.ceil((x0 + v_t + margin) / l) - start) / l)


class TrainScene(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="green_train_")
        with open(SCENE, "rb") as f:
            cls.scene = tomllib.load(f)
        cls.cut = tomllib.loads(soil_scene_text.train_cut())

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def test_the_train_of_the_sources(self):
        train = cars(self.scene)
        self.assertEqual(len(train), 8)
        self.assertEqual(self.scene["vehicle"]["speed_kmh"], 300.0)
        length = sum(c["front_overhang"] + 2.0 * c["bogie_semi_spacing"] + c["rear_overhang"]
                     for c in train)
        self.assertAlmostEqual(length, 200.32, delta=1e-9)
        for k, c in enumerate(train):
            # one rail's half of the car: axle load (both rails) in tonnes
            axle = 2.0 * (c["body_mass"] + 2.0 * c["bogie_mass"] + 4.0 * c["wheelset_mass"]) / 4.0
            self.assertAlmostEqual(axle, 15500.0 if k not in (3, 4) else 13850.0, delta=1e-9)
            self.assertEqual((c["bogie_semi_spacing"], c["wheelset_semi_base"]), (8.6875, 1.25))
        self.assertEqual([c["front_overhang"] for c in (train[0], train[-1])], [4.76, 3.7])
        self.assertEqual([c["rear_overhang"] for c in (train[0], train[-1])], [3.7, 4.76])
        self.assertEqual(self.scene["soil"]["receivers"], [8.0, 16.0, 32.0, 64.0])
        self.assertEqual(self.scene["soil"]["model"], "green")

    def test_the_study_of_the_cut_scene(self):
        path = os.path.join(self.work, "train_cut.toml")
        with open(path, "w") as f:
            f.write(soil_scene_text.train_cut())
        out = os.path.join(self.work, "study")
        env = dict(os.environ, OMP_NUM_THREADS="1", XDG_CACHE_HOME=self.work)
        p = subprocess.run(["/usr/bin/python3", "-m", "green_soil.study", "--scene", path,
                            "--out", out, "--master", os.path.join(BIN, "master")],
                           cwd=SRC, capture_output=True, text=True, timeout=300, env=env)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr[-3000:])
        run = os.path.join(out, "runs", "green", "ss-xt-jacobi")
        with open(os.path.join(run, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(summary["status"], "ok")
        self.assertEqual(summary["windows"]["ss"], 1e-3)
        # The wheels span the train less the leading and trailing overhangs
        # and half wheelbases: 200.32 - 2 (4.76 - 1.25) = 193.30 m.
        with open(os.path.join(run, "soil_forces.csv")) as f:
            head = next(csv.reader(f))
        self.assertEqual(len(head) - 1, auto_count(self.cut, 193.30))
        with open(os.path.join(run, "receivers.csv")) as f:
            rows = list(csv.reader(f))
        self.assertEqual(len(rows) - 1, 100)  # the soil's 100 windows of 1 ms
        self.assertAlmostEqual(float(rows[1][0]), 1e-3, delta=1e-12)
        with open(os.path.join(out, "REPORT.md")) as f:
            report = f.read()
        # 0.1 s: lines 10 Hz apart; the 50 Hz band is 11.5 Hz wide, the 40 Hz
        # band 9.2 Hz; the taper from 96 Hz ends the bands at 80 Hz (upper edge 89 Hz).
        levels = support.report_rows(report, "## Levels at the receivers")
        self.assertEqual([r[0] for r in levels], ["8 m", "16 m"])
        for r in levels:
            self.assertEqual(r[3], "50.1-79.4", r)
            self.assertEqual(r[4], "the 0.1 s record / the taper from 96 Hz (0.8 f_max)", r)
        # vibration.csv states the same bands, the two-way run's and the
        # one-way check's.
        for folder in (run, os.path.join(out, "runs", "two-step")):
            with open(os.path.join(folder, "vibration.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(len(rows), 2)
            for r in rows:
                self.assertEqual((float(r["resolved_from_hz"]), float(r["resolved_to_hz"])),
                                 (float("%.9g" % 10 ** 1.7), float("%.9g" % 10 ** 1.9)), folder)
        check = support.report_rows(report, "### Checks run by this study")
        self.assertEqual(check[0][-1], "pass", check)


if __name__ == "__main__":
    unittest.main()
