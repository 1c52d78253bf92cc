"""A force ramped up over one step and held: the running integral of the
receivers' velocity kernels (the participant's own, green_soil/track.py)
equals the static displacement once the waves have passed, and the
footprint's displacement kernel settles on its static flexibility.

On a homogeneous elastic half-space (nu = 1/4) the static value is
Boussinesq's, in closed form (greens.static_point); on the ground-vibration
scene's layers without damping it is the layered static solution (the
Papkovich-Neuber basis at w = 0). Before the fix the velocity kernels
lacked the sum of the responses' precursor (what the cut at f_max puts
before t = 0): their integral grew without end, 1.19 times the static
value 50 ms after the Rayleigh wave at 5 m, 2.6 times at 0.5 s."""
import atexit
import math
import shutil
import tempfile
import unittest

import numpy as np

import support
from green_soil import greens, outputs, responses as R, track

CACHE = tempfile.mkdtemp(prefix="green_held_")  # this test's own cache of Green's functions
atexit.register(shutil.rmtree, CACHE, True)
H = 1e-4  # s, the CI scene's macro step
MEMORY = 0.6  # s
FOOTPRINT = (0.0, 0.75, 0.6, 1.3)  # x, y, along, across (one rail's share of a sleeper)
DISTANCES = (5.0, 8.0, 16.0, 32.0)


def integrated_velocity(layers):
    """(times, integral of each receiver's velocity kernel by the trapezoid
    rule from rest, static displacement per receiver, the soil)."""
    soil = track.TrackSoil(layers, [FOOTPRINT], [(0.0, d) for d in DISTANCES], H, MEMORY,
                           f_max=150.0, workers=1, cache_dir=CACHE)
    v = soil.R[::-1, :, 0]  # by lag: the velocity at the end of step m + 1
    t = H * np.arange(1, soil.M + 1)
    integral = H * (np.cumsum(v, axis=0) - 0.5 * v)
    y = FOOTPRINT[1]
    offsets = [(0.0, d - y) for d in DISTANCES] + [(0.0, d + y) for d in DISTANCES]
    _, points = R.spectra(layers, soil.fp, [], offsets, [0.0])
    static = (points[:len(DISTANCES), 0] + points[len(DISTANCES):, 0]).real
    return t, integral, static, soil


class HeldForce(unittest.TestCase):
    def test_half_space_against_boussinesq(self):
        layer = support.HALF_SPACE[0]
        t, integral, static, soil = integrated_velocity(support.HALF_SPACE)
        scale = (1.0 - layer.poisson) / layer.shear_modulus
        c_r = 0.9194 * layer.shear_speed  # Rayleigh speed at nu = 1/4
        for k, d in enumerate(DISTANCES):
            bous = scale * (greens.static_point(0.0, d - FOOTPRINT[1], 0.6, 1.3)
                            + greens.static_point(0.0, d + FOOTPRINT[1], 0.6, 1.3))
            self.assertLess(abs(static[k] / bous - 1.0), 1e-9)
            # From 50 ms after the Rayleigh wave has crossed the farther
            # footprint (the cut at f_max rings that long): measured 2.7e-3
            # at 5 m, 4e-4 beyond.
            after = t >= (d + FOOTPRINT[1] + 0.65) / c_r + 0.05
            err = np.abs(integral[after, k] / bous - 1.0)
            self.assertLess(err.max(), 5e-3, "at %g m: %.3g at t = %.3f s"
                            % (d, err.max(), t[after][np.argmax(err)]))
        # The footprint's own displacement kernel on its static flexibility
        # (measured 3e-7 at the memory's end).
        own = soil.S[0, 0, 0] / soil.elastic_static[0, 0] - 1.0
        self.assertLess(abs(own), 1e-4)

    def test_layered_static_value(self):
        # No damping (the hysteretic loss creeps, spectral.py). The layered
        # ground's slow dispersed waves have passed 16 m by 0.45 s (not yet
        # 32 m: 0.19 there at 0.45 s, 0.01 at 0.59 s).
        t, integral, static, _ = integrated_velocity(support.elastic(support.LAYERED))
        late = t >= 0.45
        for k, d in enumerate(DISTANCES[:3]):
            err = np.abs(integral[late, k] / static[k] - 1.0)
            # Measured 1.0e-2 at 5 m (what the cut at f_max puts before
            # t = 0 there), 1.0e-3 at 8 m, 5.4e-3 at 16 m.
            self.assertLess(err.max(), 0.015, "at %g m: %.3g" % (d, err.max()))

    def test_receivers_files_point_z_up(self):
        # The kernels are the velocity along the force (down); the files
        # (receivers.csv, vibration.csv's rows, the history channels) give
        # v_z up, as the FE soil's: under a held downward force the ground
        # settles, so the integral of the written v_z is minus the static
        # displacement.
        t, _, static, soil = integrated_velocity(support.HALF_SPACE)
        rows = soil.R[::-1, :, 0]  # the vertical rows a held unit force gives, step by step
        vz = outputs.components(rows, len(DISTANCES))[:, :, 2]
        written = H * (np.cumsum(vz, axis=0) - 0.5 * vz)
        late = t >= 0.45
        for k in range(3):
            self.assertLess(abs(written[late, k].mean() / static[k] + 1.0), 5e-3)
        self.assertEqual(outputs.vertical_up(rows[-1]).tolist(), (-rows[-1]).tolist())


if __name__ == "__main__":
    unittest.main()
