"""An open trench on a homogeneous half-space (c_S = 100 m/s, nu = 1/4,
rho = 2000 kg/m^3, no damping) under a narrow-band vertical load: a 25 Hz
tone burst (four cycles under a sine-squared window) on the middle one of
31 sleepers' footprints. The trench, 0.4 m wide and 4.5 lambda_R long,
stands 6 m from the track's axis (about 1.6 lambda_R, lambda_R = c_R / f =
3.68 m); nine receivers behind it, 0.5 to 1.5 lambda_R behind its back
face and 0 to 1 lambda_R along the track from the loaded sleeper, give the
amplitude reduction ratio A_R: the RMS over them of each one's Fourier
amplitude at 25 Hz with the trench over that without it.

Woods (1968, "Screening of surface waves in soils", J. Soil Mech. Found.
Div. ASCE 94(4), 951-979) found that a trench must reach at least about
0.6 lambda_R for significant screening, and one 1.19 lambda_R deep
reduced the amplitude by 88 % over a small area behind it. `Screening`:
a deep trench (1.2 lambda_R) screens, a shallow one (0.2 lambda_R) hardly.
`Refinement`: the deep trench's reduction in dB on the rule's mesh (10
elements per Rayleigh wavelength at 25 Hz) against a coarser one (7.5)."""
import math
import sys
import unittest
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE

from fe_soil import config
from fe_soil.model import FESoil
from fe_soil.params import rayleigh_speed

F0, CYCLES, FORCE = 25.0, 4, 1e4
C_R = rayleigh_speed(HALF_SPACE.shear_speed, HALF_SPACE.poisson)
L_R = C_R / F0
N_SLEEPERS, MIDDLE = 31, 15
DISTANCE, WIDTH, LENGTH = 6.0, 0.4, 4.5 * L_R


def block(depth_ratio, n=10.0):
    """The block of the [soil] keys with a trench depth_ratio lambda_R deep
    (0: none), the receivers replaced by the grid behind the trench."""
    table = {"model": "fe", "f_max": F0, "elements_per_wavelength": n, "growth": 1.15,
             "receivers": [8.0], "resolve_to": 13.0, "fine_depth": 8.5, "depth": 14.0,
             "margin": 6.0, "margin_along": 6.0, "static_reach": 0.0,
             "footprint_compliance": False,
             "layers": [{"density": HALF_SPACE.density, "shear_wave_speed": HALF_SPACE.shear_speed,
                         "poisson": HALF_SPACE.poisson}]}
    if depth_ratio:
        table["measures"] = [{"kind": "trench", "distance": DISTANCE, "width": WIDTH,
                              "depth": depth_ratio * L_R, "length": LENGTH}]
    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.6, y=0.0)
                for i in range(N_SLEEPERS)]
    p = config.block_params(config.parse(table), sleepers)[0]
    xc = p.footprints[MIDDLE].x
    p.receivers = [(xc + dx * L_R, DISTANCE + WIDTH + dy * L_R)
                   for dx in (-1.0, -0.5, 0.0) for dy in (0.5, 1.0, 1.5)]
    return p


def amplitudes(p):
    """Each receiver's Fourier amplitude of v_z at F0 over the record (the
    burst's passage past the farthest receiver)."""
    soil = FESoil(p)
    H = soil.dt
    T = CYCLES / F0

    def force(t):
        if t >= T:
            return 0.0
        return FORCE * math.sin(2 * math.pi * F0 * t) * math.sin(math.pi * t / T) ** 2

    far = max(math.hypot(x - p.footprints[MIDDLE].x, y) for x, y in p.receivers)
    a, b = np.zeros(N_SLEEPERS), np.zeros(N_SLEEPERS)
    for k in range(int(math.ceil((T + (far + 2.0) / C_R) / H))):
        a[MIDDLE], b[MIDDLE] = force(k * H), force((k + 1) * H)
        soil.advance(k * H, H, a, b)
    t, v = soil.receiver_series()
    return np.abs(np.exp(-2j * math.pi * F0 * t) @ v[:, :, 2]) * H


def reduction(with_trench, without):
    """A_R: the RMS of the amplitudes with the trench over that without."""
    return float(np.sqrt(np.sum(with_trench**2) / np.sum(without**2)))


class Screening(unittest.TestCase):
    def test_a_deep_trench_screens_and_a_shallow_one_hardly(self):
        # Measured (2026-12-02, about 296,000 DOFs, 45 s on one core): A_R
        # 0.367 at 1.2 lambda_R, 0.844 at 0.2 lambda_R (with the measure's
        # neighbouring planes placed otherwise: 0.287 and 0.798). The bounds
        # leave that spread as margin.
        ref = amplitudes(block(0.0))
        deep = reduction(amplitudes(block(1.2)), ref)
        shallow = reduction(amplitudes(block(0.2)), ref)
        print("A_R deep %.3f shallow %.3f" % (deep, shallow))
        self.assertLess(deep, 0.45)
        self.assertGreater(shallow, 0.65)
        self.assertLess(deep, 0.5 * shallow)


class Refinement(unittest.TestCase):
    def test_the_deep_trenchs_reduction_on_two_meshes(self):
        # -20 log10 A_R of the deep trench at 7.5 and 10 elements per
        # Rayleigh wavelength: measured (2026-12-02) 9.49 and 8.70 dB, 0.79
        # dB apart (41 s on one core).
        il = []
        for n in (7.5, 10.0):
            ref = amplitudes(block(0.0, n))
            il.append(-20.0 * math.log10(reduction(amplitudes(block(1.2, n)), ref)))
        print("IL coarse %.2f dB fine %.2f dB difference %.2f dB" % (il[0], il[1], il[0] - il[1]))
        self.assertGreater(min(il), 20.0 * math.log10(1.0 / 0.45))
        self.assertLess(abs(il[0] - il[1]), 1.5)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + sys.argv[1:])
