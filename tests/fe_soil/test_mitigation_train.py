"""The insertion-loss study under the scene's own train ([soil.mitigation]
load = "train", fe_soil/study_load.py) on
scenes/ground_vibration_trench_ci.toml, its record shortened (RECORD s) and
its mesh coarsened (MESH m) to CI size, run as a user runs it (python3 -m
fe_soil.mitigation --scene FILE --out DIR --master BIN/master) and judged
on what it wrote:

- the forces are those of the master's monolithic run of the scene's car on
  the lumped soil fitted to the reference block (two_step.fit_lumped, the
  fit repeated here), one column per sleeper of the track, and their first
  row carries exactly the car's weight on one rail (g (M_c + 2 M_t + 4 M_w),
  the half masses of the scene; the track's own weight is not a load of the
  model);
- the reference variant equals those forces applied one way to a plain
  block built here (its table with variant = "reference", as a plain run
  builds it), to 1e-12 of each receiver's peak over the whole record,
  though the study ran it on the block it fitted the lumped soil to;
- the trench's statics started from the reference's solution: fewer
  iterations than from zero, the same static state to the solver's
  tolerance;
- with [soil.mitigation] track_window the block carries the sleepers
  within half of it of the track's middle, their columns of the vehicle's
  forces, and the load's text says how many of the track's;
- behind the trench (6 and 9 m) the PPV is lower than without it;
- REPORT.md names the load: the car, its speed and its sleepers;
- the Ricker force's keys beside load = "train", an unknown load and a
  missing master program are refused by name.
Usage: test_mitigation_train.py BIN_DIR"""
import os
import subprocess
import sys
import tempfile
import tomllib
import unittest

import numpy as np

from support import HALF_SPACE  # noqa: F401  (skips without dolfinx)

from fe_soil import config, path_measures, scene_file, study_load, two_step
from fe_soil.model import FESoil

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(SRC, "build", "bin")
SCENE = os.path.join(SRC, "scenes", "ground_vibration_trench_ci.toml")
RECORD = 0.15  # s
MESH = 0.7  # m


def read_losses(path):
    """insertion_loss.csv as {measure: [{quantity: IL dB} per receiver]}
    (the whole-record quantities: ppv, kb_fmax, overall)."""
    losses = {}
    with open(path) as f:
        next(f)
        for line in f:
            measure, receiver, _, quantity, _, il = line.strip().split(",")
            if quantity == "band":
                continue
            per = losses.setdefault(measure, {})
            per.setdefault(receiver, {})[quantity] = float(il)
    return {m: list(per.values()) for m, per in losses.items()}


class TrainLoad(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(SCENE, "rb") as f:
            cls.scene = tomllib.load(f)
        cls.scene["soil"]["mitigation"] = {"load": "train", "duration": RECORD}
        cls.scene["soil"]["mesh_size"] = MESH
        cls.out = tempfile.mkdtemp(prefix="mitigation_train_")
        # The study as a user runs it: the command on a scene file, the
        # master given by --master; what the tests read is what it wrote.
        path = os.path.join(cls.out, "scene.toml")
        with open(path, "w") as f:
            f.write(scene_file.toml_text(cls.scene) + "\n")
        cls.cli = subprocess.run(
            [sys.executable, "-m", "fe_soil.mitigation", "--scene", path, "--out", cls.out,
             "--master", os.path.join(BIN, "master")],
            cwd=SRC, capture_output=True, text=True, timeout=600)
        if cls.cli.returncode != 0:
            raise AssertionError("the study failed:\n" + cls.cli.stdout + cls.cli.stderr)
        variants = [path_measures.REFERENCE] + [m["name"] for m in cls.scene["soil"]["measures"]]
        cls.records = {v: np.load(os.path.join(cls.out, "runs", v, "receivers.npz"))["v"]
                       for v in variants}
        cls.losses = read_losses(os.path.join(cls.out, "insertion_loss.csv"))
        cls.train_run = os.path.join(cls.out, "train", "lumped", "monolithic")
        head, cls.forces = two_step.read_csv(os.path.join(cls.train_run, "soil_forces.csv"))
        cls.xs = [float(x) for x in head[1:]]

    def plain_block(self):
        cfg = config.parse(dict(self.scene["soil"], variant="reference"))
        fps = two_step.footprints(self.scene, self.xs)
        return FESoil(config.block_params(cfg, fps)[0]), cfg

    def test_the_forces_carry_the_cars_weight_at_every_sleeper(self):
        v = self.scene["vehicle"]
        weight = self.scene["simulation"]["gravity"] * (
            v["body_mass"] + 2 * v["bogie_mass"] + 4 * v["wheelset_mass"])
        self.assertAlmostEqual(float(self.forces[0, 1:].sum()) / weight, 1.0, delta=1e-9)
        spacing = self.scene["sleepers"]["spacing"]
        np.testing.assert_allclose(np.diff(self.xs), spacing, rtol=1e-9)
        self.assertGreater(len(self.xs), 40)
        np.testing.assert_allclose(np.diff(self.forces[:, 0]),
                                   self.scene["simulation"]["macro_step"], rtol=1e-6)
        self.assertAlmostEqual(self.forces[-1, 0], RECORD, delta=1e-9)
        # the car moves: the sleeper under the largest force is not the same
        peak = np.argmax(self.forces[:, 1:], axis=1)
        self.assertGreater(int(peak[-1] - peak[0]), 5)

    def test_the_lumped_soil_is_fitted_to_the_reference_block(self):
        soil, _ = self.plain_block()
        kf, kc = two_step.fit_lumped(soil, len(self.xs))
        with open(os.path.join(self.out, "train", "lumped.toml"), "rb") as f:
            lumped = tomllib.load(f)["soil"]
        self.assertAlmostEqual(lumped["stiffness"] / kf, 1.0, delta=1e-8)
        self.assertAlmostEqual(lumped["coupling_stiffness"] / kc, 1.0, delta=1e-8)
        self.assertEqual(lumped["model"], "lumped")

    def test_the_vehicles_run_is_the_scene_with_the_studys_end_time(self):
        with open(os.path.join(self.out, "train", "lumped.toml"), "rb") as f:
            written = tomllib.load(f)
        for key in set(self.scene) - {"soil", "output", "simulation"}:
            self.assertEqual(written[key], self.scene[key], key)
        self.assertEqual(written["simulation"], dict(self.scene["simulation"], end_time=RECORD))
        self.assertEqual(written["output"], {"ballast_forces": True})

    def test_the_two_step_scene_of_a_scene_with_a_study_load_runs(self):
        # two_step's lumped scene (fe_soil.study) of this scene, whose [soil]
        # has [soil.mitigation] and [[soil.layers]] tables: the master takes it
        cfg = config.parse(self.scene["soil"])
        path = two_step.lumped_scene(SCENE, self.scene, cfg, 3e7, 7e7,
                                     os.path.join(self.out, "two_step.toml"))
        with open(path, "rb") as f:
            written = tomllib.load(f)
        self.assertEqual(sorted(written["soil"]), ["coupling_damping", "coupling_stiffness",
                                                   "damping", "mass", "model", "stiffness"])
        p = subprocess.run([os.path.join(BIN, "master"), "run", "--scene", path, "--case",
                            "monolithic", "--check"], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)

    def test_the_reference_is_the_forces_one_way_into_a_plain_block(self):
        soil, _ = self.plain_block()
        H = self.scene["simulation"]["macro_step"]
        t, v = two_step.one_way(soil, self.forces[:, 1:], self.forces[:, 0], H)
        ref = self.records[path_measures.REFERENCE]
        self.assertEqual(ref.shape, v.shape)
        for k in range(v.shape[1]):
            scale = np.abs(v[:, k, :]).max()
            self.assertGreater(scale, 0.0)
            self.assertLess(float(np.abs(ref[:, k, :] - v[:, k, :]).max() / scale), 1e-12, k)
        saved = np.load(os.path.join(self.out, "runs", "reference", "receivers.npz"))
        np.testing.assert_array_equal(saved["t"], t)

    def test_a_variants_statics_starts_from_the_references(self):
        reference, cfg = self.plain_block()
        fps = two_step.footprints(self.scene, self.xs)
        load = self.forces[0, 1:]
        reference.statics(load)
        trench = [FESoil(config.block_params(dict(cfg, variant="trench"), fps)[0])
                  for _ in range(2)]
        trench[1].start_statics_from(reference.static_solutions())
        for soil in trench:
            soil.static_iterations = 0
            soil.statics(load)
        fresh, started = (s.static_iterations for s in trench)
        self.assertLess(started, fresh, (fresh, started))
        scale = float(np.abs(trench[0].u).max())
        self.assertLess(float(np.abs(trench[1].u - trench[0].u).max()) / scale, 1e-9)
        # where the DOFs are other points (another mesh), the start is zero
        other = FESoil(config.block_params(dict(cfg, mesh_size=MESH * 1.2), fps)[0])
        other.start_statics_from(reference.static_solutions())
        self.assertEqual(other._static_start, [])
        print("static CG iterations of the trench: %d from zero, %d from the reference's"
              % (fresh, started))

    def test_a_track_window_carries_the_sleepers_around_the_middle(self):
        cfg = config.parse(self.scene["soil"])
        load = study_load.load_keys({"load": "train", "duration": RECORD, "track_window": 12.0})
        out = os.path.join(self.out, "window")
        train = study_load.make(self.scene, load, cfg,
                                lambda fps: FESoil(config.block_params(cfg, fps)[0]),
                                os.path.join(BIN, "master"), out, os.path.dirname(SCENE))
        mid = 0.5 * (self.xs[0] + self.xs[-1])
        want = [x for x in self.xs if abs(x - mid) <= 6.0 + 1e-9]
        self.assertEqual([f.x for f in train.footprints], want)
        self.assertTrue(3 <= len(want) < len(self.xs), (len(want), len(self.xs)))
        head, data = two_step.read_csv(os.path.join(out, "lumped", "monolithic", "soil_forces.csv"))
        columns = [1 + [float(x) for x in head[1:]].index(x) for x in want]
        np.testing.assert_array_equal(train.forces, data[:, columns])
        self.assertIn("The block carries %d of the track's %d sleepers, those within 6 m of its "
                      "middle ([soil] mitigation.track_window 12 m): the others' forces are left "
                      "out." % (len(want), len(self.xs)), train.text())

    def test_behind_the_trench_the_ppv_is_lower(self):
        per = self.losses["trench"]
        self.assertEqual(len(per), 3)
        self.assertTrue(all(il["ppv"] > 0.0 for il in per[1:]), [il["ppv"] for il in per])

    def test_the_command_says_what_it_wrote(self):
        self.assertIn("mitigation: wrote %s" % os.path.join(self.out, "REPORT.md"),
                      self.cli.stdout)
        self.assertTrue(os.path.isfile(os.path.join(self.out, "figures", "insertion_loss.png")))

    def test_the_report_names_the_train(self):
        with open(os.path.join(self.out, "REPORT.md")) as f:
            text = f.read()
        self.assertIn("the scene's vehicle (car) at 160 km/h on its track, by the two-step method",
                      text)
        self.assertIn("a variant's own effect on them is left out", text)
        self.assertIn("each of its %d sleepers" % len(self.xs), text)

    def test_wrong_keys_are_refused_by_name(self):
        for table, pattern in (
                ({"load": "train", "frequency": 20.0},
                 r"mitigation\.frequency is a key of the Ricker force"),
                ({"load": "trains"}, r"mitigation\.load must be one of \"ricker\", \"train\""),
                ({"load": "train", "duration": 0.0}, r"mitigation\.duration must be > 0"),
                ({"track_window": 10.0}, r"mitigation\.track_window is a key of the train's"),
                ({"load": "train", "track_window": 0.0},
                 r"mitigation\.track_window must be > 0")):
            with self.assertRaisesRegex(config.ConfigError, pattern):
                study_load.load_keys(table)
        cfg = config.parse(self.scene["soil"])
        master = os.path.join(BIN, "master")
        train = study_load.load_keys({"load": "train"})
        for scene, where, pattern in (
                (self.scene, os.path.join(self.out, "nowhere"),
                 r"give it with --master BIN/master \(not found: .*nowhere\)"),
                (self.scene, None, r"give it with --master BIN/master$"),
                (dict(self.scene, vehicle=dict(self.scene["vehicle"], fmu={"file": "v.fmu"})),
                 master, r"\[vehicle\.fmu\] cannot"),
                (self.scene, master, None)):
            load = train if pattern else study_load.load_keys({"load": "train",
                                                               "duration": 0.01234})
            with self.assertRaisesRegex(config.ConfigError, pattern or
                                        r"mitigation\.duration 0\.01234 s must be a whole "
                                        r"number of at least 10 macro steps of 0\.0001 s"):
                study_load.make(scene, load, cfg, None, where, self.out)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
