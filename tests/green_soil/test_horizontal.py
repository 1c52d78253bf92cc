"""The receivers' horizontal velocities (green_soil/track.py with
horizontal=True, radial.point_means convolved as the vertical ones are):
under a force ramped up over one step and held on a homogeneous elastic
half-space (nu = 1/4), their integrals tend to Boussinesq's radial
displacement -(1 - 2 nu)/(4 pi mu r) toward the load, averaged over the
footprint and its mirror, with the right sign in x and y; straight
across from the footprint the velocity along the rail is zero. The
vertical rows are those of a soil without the horizontal ones, bit for
bit."""
import atexit
import math
import shutil
import tempfile
import unittest

import numpy as np

import support
from green_soil import track

CACHE = tempfile.mkdtemp(prefix="green_horizontal_")  # this test's own cache of Green's functions
atexit.register(shutil.rmtree, CACHE, True)
H = 1e-4
MEMORY = 0.6
FOOTPRINT = (0.0, 0.75, 0.6, 1.3)
RECEIVERS = [(3.0, 8.0), (0.0, 8.0), (-3.0, 16.0), (5.0, 5.0)]
LAYER = support.HALF_SPACE[0]


def boussinesq(px, py):
    """(u_x, u_y) of a unit force spread over the footprint and its mirror
    (y -> -y): the point load's radial displacement, averaged by 40 x 40
    Gauss points over each rectangle."""
    x, w = np.polynomial.legendre.leggauss(40)
    _, yc, a, b = FOOTPRINT[0], FOOTPRINT[1], FOOTPRINT[2], FOOTPRINT[3]
    sx, sy = np.meshgrid(0.5 * a * x, 0.5 * b * x, indexing="ij")
    wq = np.outer(0.5 * w, 0.5 * w)
    out = np.zeros(2)
    for centre in (yc, -yc):
        ex, ey = px - sx, py - (centre + sy)
        r = np.hypot(ex, ey)
        u_r = -(1.0 - 2.0 * LAYER.poisson) / (4.0 * math.pi * LAYER.shear_modulus * r)
        out += [np.sum(wq * u_r * ex / r), np.sum(wq * u_r * ey / r)]
    return out


class Horizontal(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.soil = track.TrackSoil(support.HALF_SPACE, [FOOTPRINT], RECEIVERS, H, MEMORY,
                                   f_max=150.0, workers=1, horizontal=True, cache_dir=CACHE)
        v = cls.soil.R[::-1, :, 0]
        cls.t = H * np.arange(1, cls.soil.M + 1)
        cls.integral = H * (np.cumsum(v, axis=0) - 0.5 * v)

    def test_rows(self):
        self.assertEqual(self.soil.R.shape, (self.soil.M, 3 * len(RECEIVERS), 1))
        vertical = track.TrackSoil(support.HALF_SPACE, [FOOTPRINT], RECEIVERS, H, MEMORY,
                                   f_max=150.0, workers=1, cache_dir=CACHE)
        self.assertTrue(np.array_equal(vertical.R, self.soil.R[:, :len(RECEIVERS)]))

    def test_static_limit_against_boussinesq(self):
        n = len(RECEIVERS)
        for k, (px, py) in enumerate(RECEIVERS):
            ref = boussinesq(px, py)
            r = math.hypot(px, py - FOOTPRINT[1])
            late = self.t >= 0.2
            for c, name in ((0, "x"), (1, "y")):
                got = self.integral[:, (1 + c) * n + k]
                if px == 0.0 and c == 0:  # straight across: no motion along the rail
                    self.assertEqual(np.abs(got).max(), 0.0)
                    continue
                self.assertLess(ref[c] * (px, py)[c], 0.0)  # toward the load
                # Lamb's horizontal displacement settles slowly after the
                # waves (the vertical one is static from the Rayleigh
                # arrival on): measured |error| about 0.3 to 1.2 times
                # (r / c_S t)^2 from 0.2 s on (0.13 % to 1.2 % at 0.6 s).
                err = np.abs(got[late] / ref[c] - 1.0)
                bound = 2.0 * (r / (LAYER.shear_speed * self.t[late])) ** 2 + 2e-3
                worst = int(np.argmax(err / bound))
                self.assertTrue((err <= bound).all(), "%s at (%g, %g): %.3g at t = %.3f s"
                                % (name, px, py, err[worst], self.t[late][worst]))


if __name__ == "__main__":
    unittest.main()
