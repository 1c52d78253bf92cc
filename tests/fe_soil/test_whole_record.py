"""The whole record on the graded mesh of the scene keys: the homogeneous
half-space (c_S = 100 m/s, rho = 2000, nu = 1/4, no damping) under a
10 kN 7.5 Hz Ricker on the middle one of 21 sleepers' 0.25 x 2.5 m
footprints, at f_max 10 Hz with the keys' defaults otherwise (absorbing
layers over the graded zones, growth 1.1), the vertical velocity at 4 and
8 m from the load's start to 0.6 s (after the slowest wave the block can
send back has passed) against the closed form of Pekeris averaged over the
footprint (fe_soil/record_check.py). The same mesh without the layers
(absorbing_reflection = 1, the Lysmer-Kuhlemeyer boundary alone) is the
control: what comes back then fails the bound."""
import unittest
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE

from fe_soil import config, lamb, record_check
from fe_soil.model import FESoil

F, FC, T_END, MIDDLE = 1e4, 7.5, 0.6, 10
T0 = 1.2 / FC


def block(**keys):
    table = {"model": "fe", "f_max": 10.0, "growth": 1.1, "receivers": [4.0, 8.0, 16.0, 32.0],
             "resolve_to": 16.0, "static_reach": 0.0,
             "layers": [{"density": HALF_SPACE.density, "shear_wave_speed": HALF_SPACE.shear_speed,
                         "poisson": HALF_SPACE.poisson}]}
    table.update(keys)
    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0) for i in range(21)]
    return config.block_params(config.parse(table), sleepers)[0]


def whole_record(p):
    """{distance: measures} at 4 and 8 m."""
    soil = FESoil(p)
    f = lamb.ricker(FC, T0)[0]
    H = soil.dt
    before, after = np.zeros(21), np.zeros(21)
    for k in range(int(np.ceil(T_END / H))):
        before[MIDDLE], after[MIDDLE] = F * f(k * H), F * f((k + 1) * H)
        soil.advance(k * H, H, before, after)
    t, v = soil.receiver_series()
    fp = p.footprints[MIDDLE]
    out = {}
    for i, (x, y) in enumerate(p.receivers[:2]):
        ref = record_check.footprint_reference(t, (x, y), (fp.x, fp.y, fp.along, fp.across),
                                               HALF_SPACE.shear_modulus, HALF_SPACE.shear_speed,
                                               F, FC, T0)
        end = record_check.direct_end(T0 - 1.0 / FC, y, (p.length, p.half_width, p.depth),
                                      HALF_SPACE.shear_speed)
        out[y] = record_check.compare(t, -v[:, i, 2], ref, T0, end, p.f_max)
    return out


class WholeRecord(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.layers = whole_record(block())
        cls.bare = whole_record(block(absorbing_reflection=1.0))

    def test_absorbing_layers_pass_the_whole_record(self):
        # Measured at 4 / 8 m: nRMS 0.107 / 0.182, PPV +0.3 % / -0.9 %,
        # KB_Fmax +1.2 % / +0.9 %; direct waves: peak +0.5 % / -1.0 %, nRMS
        # 0.032 / 0.076 (the arrival, +2.2 % / +1.8 %, is the coarse CI
        # mesh's dispersion: +0.9 % at f_max 20). The band levels are not
        # asserted: the lowest bands (3-6 Hz) are off by 2.7 / 5.2 dB.
        for r, m in self.layers.items():
            msg = f"{r} m: {m}"
            self.assertLess(m["nrms"], 0.25, msg)
            self.assertLess(abs(m["ppv"]), 0.05, msg)
            self.assertLess(abs(m["kb"]), 0.10, msg)
            self.assertLess(abs(m["peak"]), 0.10, msg)
            self.assertLess(m["direct_nrms"], 0.15, msg)

    def test_the_layers_take_out_what_the_mesh_alone_sends_back(self):
        # The same mesh without the layers: nRMS 0.138 / 0.243 at 4 / 8 m
        # (0.77 and 0.75 of it with them).
        for r in self.layers:
            self.assertLess(self.layers[r]["nrms"], 0.85 * self.bare[r]["nrms"],
                            f"{r} m: {self.layers[r]['nrms']} against {self.bare[r]['nrms']}")

    def test_the_previous_rule_fails(self):
        # growth 1.25, the rule's spacing to the top of the half-space only,
        # no layers (the scene's mesh before): nRMS 0.326 / 0.476 at 4 / 8 m.
        old = whole_record(block(growth=1.25, fine_depth=0.0, absorbing_reflection=1.0))
        self.assertAlmostEqual(old[8.0]["nrms"], 0.476, delta=0.02)
        self.assertGreater(min(m["nrms"] for m in old.values()), 0.25, old)


if __name__ == "__main__":
    unittest.main()
