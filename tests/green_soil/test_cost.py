"""The Green's-function soil's joint bounds (green_soil/cost.py): keys each
within its own limits whose soil would not fit or not be built in time
are refused by the check the master runs (--check-configure), within
seconds and naming the keys: a top layer 1e-6 m thick, a receiver at
10 km, a top layer at c_S = 0.5 m/s, memory = 2 s over a 2 s run on the
car scene. The shipped scenes' soils are accepted; the closed-form count
of the wavenumber grid is that of greens.k_grid; the estimate's defaults
are greens.Discretisation's."""
import contextlib
import io
import math
import os
import sys
import time
import tomllib
import unittest

import support  # noqa: F401  (skips without scipy; puts the checkout on the path)

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SRC, "sdk", "python"))

from green_soil import cost, greens  # noqa: E402
from green_soil.participant import GreenSoilParticipant  # noqa: E402
from railcosim_sdk.server import check_configure  # noqa: E402
from railcosim_sdk.wire import pb  # noqa: E402

# scene, footprints (its track's sleepers), the soil's step H
SCENES = {"ci": ("ground_vibration_green_ci.toml", 52, 1e-4),
          "car": ("ground_vibration_green.toml", 124, 1e-4),
          "train": ("ground_vibration_train.toml", 682, 1e-3)}


def toml(soil):
    """The [soil] table as Configure.own_config carries it."""
    value = lambda v: "[%s]" % ", ".join(map(repr, v)) if isinstance(v, list) else (  # noqa: E731
        '"%s"' % v if isinstance(v, str) else repr(v))
    lines = ["%s = %s" % (k, value(v)) for k, v in soil.items() if k != "layers"]
    for layer in soil.get("layers", []):
        lines += ["[[layers]]"] + ["%s = %s" % (k, value(v)) for k, v in layer.items()]
    return "\n".join(lines)


def configure(scene, soil=None, end_time=None):
    name, n, H = SCENES[scene]
    with open(os.path.join(SRC, "scenes", name), "rb") as f:
        doc = tomllib.load(f)
    c = pb.Configure()
    c.participant = "soil"
    c.macro_step = H
    c.end_time = doc["simulation"]["end_time"] if end_time is None else end_time
    c.own_config = toml(soil(doc["soil"]) if soil else doc["soil"])
    i = c.interfaces.add()
    i.cut, i.peer, i.upper = "ss", "track", False
    i.receives.append(pb.FORCE)
    i.sends.extend([pb.DISPLACEMENT, pb.VELOCITY])
    for k in range(n):
        i.x.append(0.6 * k)
        f = i.footprints.add()
        f.x, f.y, f.length, f.width = 0.6 * k, 0.75, 0.6, 0.5
    return c.SerializeToString()


def checked(data):
    err = io.StringIO()
    start = time.monotonic()
    with contextlib.redirect_stderr(err):
        status = check_configure(GreenSoilParticipant(), data)
    return status, err.getvalue(), time.monotonic() - start


def top(key, value):
    def change(soil):
        soil["layers"][0][key] = value
        return soil
    return change


class JointBounds(unittest.TestCase):
    def refused(self, data, *words):
        status, err, seconds = checked(data)
        self.assertEqual(status, 2, err)
        self.assertLess(seconds, 3.0)
        self.assertIn("[soil] ", err)
        for w in words:
            self.assertIn(w, err)
        return err

    def test_thin_top_layer(self):
        err = self.refused(configure("ci", top("thickness", 1e-6)), "wavenumbers",
                           "8 / the top layer's thickness = 1e-06 m", "thickness")
        self.assertIn("k_max = 8e+06 rad/m", err)

    def test_far_receiver(self):
        self.refused(configure("ci", lambda s: dict(s, receivers=[2.0, 4.0, 10000.0])),
                     "r_max = 1e+04 m", "[soil] receivers")

    def test_slow_top_layer(self):
        self.refused(configure("ci", top("shear_wave_speed", 0.5)),
                     "the top layer's shear_wave_speed = 0.5 m/s", "[soil] f_max = 150 Hz")

    def test_long_memory_over_a_long_run(self):
        err = self.refused(configure("car", lambda s: dict(s, memory=2.0), end_time=2.0),
                           "[soil] memory = 2 s", "end_time 2 s", "GiB")
        self.assertIn("M = 20000 steps", err)

    def test_too_many_footprints(self):
        self.assertRaisesRegex(cost.ConfigError, "5000 footprints", cost.check, {}, [()] * 5000,
                               [], 1e-3, 1.0)

    def test_undefined_step(self):
        for H, end in ((0.0, 1.0), (float("nan"), 1.0), (1e-3, float("inf"))):
            self.assertRaisesRegex(cost.ConfigError, "memory in steps undefined", cost.check,
                                   {}, [(0.0, 0.75, 0.6, 0.5)], [], H, end)

    def test_shipped_scenes_pass(self):
        for scene in SCENES:
            with self.subTest(scene=scene):
                status, err, seconds = checked(configure(scene))
                self.assertEqual(status, 0, err)
                self.assertLess(seconds, 3.0)

    def test_wavenumber_count_is_k_grids(self):
        d = greens.Discretisation()
        for dk_max, k_max in ((0.025, 22.1), (0.0019, 17.7), (7.85e-5, 22.1), (0.05, 0.01),
                              (0.02, 5655.0), (2e-4, 3.0), (1.0, 100.0)):
            with self.subTest(dk_max=dk_max, k_max=k_max):
                n = len(greens.k_grid(d, dk_max, k_max)[0])
                est = cost.wavenumbers(dk_max, k_max)
                self.assertGreaterEqual(est, n)
                self.assertLessEqual(est, n + 3)
        self.assertRaisesRegex(ValueError, "at most 2000000", greens.k_grid, d, 0.025, 8e6)

    def test_defaults_are_the_discretisations(self):
        d = greens.Discretisation()
        self.assertEqual((cost.K_RATIO, cost.DK_MIN, cost.PER_PERIOD, cost.K_MAX_FACTOR, cost.DR),
                         (d.k_ratio, d.dk_min, d.per_period, d.k_max_factor, d.dr))
        self.assertEqual(cost.QUAD_POINTS, 2 * d.quad_along * 2 * d.quad_across)
        self.assertTrue(math.isclose(cost.MIN_RECORD, 0.5))


if __name__ == "__main__":
    unittest.main()
