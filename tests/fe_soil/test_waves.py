"""Waves in the finite-element soil: the Rayleigh wave's speed under a
vertical impulsive load on a homogeneous half-space (nu = 1/4), and the
energy the absorbing boundary sends back against a domain twice as large."""
import unittest

import numpy as np

from support import HALF_SPACE, Footprint, SoilParams, drive, graded_nodes, ricker, uniform_nodes

from fe_soil.model import FESoil
from fe_soil.params import rayleigh_speed


def envelope_peak_time(x, dt):
    """Time of the peak of |analytic signal| (parabola through the top)."""
    n = len(x)
    weights = np.zeros(n)
    weights[0] = 1.0
    weights[1 : (n + 1) // 2] = 2.0
    if n % 2 == 0:
        weights[n // 2] = 1.0
    e = np.abs(np.fft.ifft(np.fft.fft(x) * weights))
    k = int(np.argmax(e))
    y0, y1, y2 = e[k - 1], e[k], e[k + 1]
    return (k + 0.5 * (y0 - y2) / (y0 - 2.0 * y1 + y2)) * dt


class Waves(unittest.TestCase):
    def test_rayleigh_wave_arrival(self):
        # A 12 Hz Ricker force on a 1 m square; receivers 4-16 m across the
        # track; h = 0.4 m (19 elements per Rayleigh wavelength at 12 Hz) up
        # to 17 m, growing by 1.2 per element beyond. The envelope peaks of
        # the vertical velocity against distance give the speed (fitted
        # line). Measured: 0.985 c_R (h = 0.3 m, 16 Hz: 0.980).
        fc, distances = 12.0, [4.0, 8.0, 12.0, 16.0]
        p = SoilParams(
            length=24.0, half_width=20.0, depth=10.0, layers=[HALF_SPACE],
            footprints=[Footprint(12.0, 1.0, 1.0)], receivers=[(12.0, y) for y in distances],
            x_nodes=graded_nodes(0.0, 24.0, 12.0, 0.4, 1.0, 1.2),
            y_nodes=graded_nodes(0.0, 20.0, 0.0, 0.4, 17.0, 1.2),
            z_nodes=graded_nodes(-10.0, 0.0, 0.0, 0.4, 3.0, 1.2),
        )
        soil = FESoil(p)
        H = soil.dt
        drive(soil, 1e5, fc, 1.2 / fc, 1.2 / fc + distances[-1] / 80.0, H)
        _, v = soil.receiver_series()
        peaks = [envelope_peak_time(v[:, i, 2], H) for i in range(len(distances))]
        self.assertTrue(np.all(np.diff(peaks) > 0.0), peaks)
        speed = 1.0 / np.polyfit(distances, peaks, 1)[0]
        c_r = rayleigh_speed(HALF_SPACE.shear_speed, HALF_SPACE.poisson)
        self.assertAlmostEqual(speed / c_r, 1.0, delta=0.03, msg=f"peaks {peaks}")

    def test_absorbing_boundary_against_a_domain_twice_as_large(self):
        # A 20 Hz Ricker force at the centre of a 16 x 8 x 8 m half block
        # (S) and of a 32 x 16 x 16 m one (B), h = 0.5 m. Once the direct
        # waves have left S's region (B's kinetic energy there below 1 % of
        # its peak) and before a shear wave reflected at B's boundary can be
        # back in it (32 - 8 m at c_S after the pulse's onset), S's excess
        # kinetic energy is what its boundary sent back. Measured: at most
        # 1.75 % of the peak (dashpots without springs 1.79 %); with the
        # springs alone (no dashpots) 110 %, the control that shows the
        # measure sees a reflecting boundary.
        fc, half = 20.0, (16.0, 8.0, 8.0)
        soils = []
        for scale, dashpots in ((1.0, True), (2.0, True), (1.0, False)):
            L, W, D = (scale * s for s in half)
            soils.append(FESoil(SoilParams(
                length=L, half_width=W, depth=D, layers=[HALF_SPACE],
                footprints=[Footprint(L / 2.0, 1.0, 1.0)], dashpots=dashpots,
                x_nodes=uniform_nodes(0.0, L, 0.5), y_nodes=uniform_nodes(0.0, W, 0.5),
                z_nodes=uniform_nodes(-D, 0.0, 0.5))))
        small, big, reflecting = soils
        c = big.dof_coordinates()
        inside = (abs(c[:, 0] - half[0]) <= half[0] / 2.0 + 1e-9) & (c[:, 1] <= half[1] + 1e-9) & (c[:, 2] >= -half[2] - 1e-9)
        inside = inside.astype(float)
        H = min(small.dt, big.dt)
        t0 = 1.2 / fc
        onset = t0 - 1.0 / fc
        t_end = onset + (2.0 * 2.0 * half[1] - half[1]) / HALF_SPACE.shear_speed
        e_small, e_big, e_reflecting = [], [], []
        for k in range(int(t_end / H)):
            f0, f1 = [1e5 * ricker(k * H, fc, t0)], [1e5 * ricker((k + 1) * H, fc, t0)]
            small.advance(k * H, H, f0, f1)
            big.advance(k * H, H, f0, f1)
            reflecting.advance(k * H, H, f0, f1)
            e_reflecting.append(reflecting.kinetic_energy())
            e_small.append(small.kinetic_energy())
            e_big.append(big.kinetic_energy(inside))
        e_small, e_big, e_reflecting = np.array(e_small), np.array(e_big), np.array(e_reflecting)
        peak = e_big.max()
        k_peak = int(np.argmax(e_big))
        gone = np.flatnonzero(e_big[k_peak:] < 0.01 * peak)
        self.assertGreater(len(gone), 5, "the direct waves did not leave the inner region in the window")
        window = slice(k_peak + gone[0], None)
        returned = float(np.max(e_small[window] - e_big[window]) / peak)
        self.assertLess(returned, 0.025)
        self.assertGreater(returned, 0.0)
        without_dashpots = float(np.max(e_reflecting[window] - e_big[window]) / peak)
        self.assertGreater(without_dashpots, 0.5)


if __name__ == "__main__":
    unittest.main()
