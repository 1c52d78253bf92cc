"""Static values: Boussinesq's footprint averages against closed forms, the
layered static solution (the Papkovich-Neuber basis) through the spatial
machinery against a wavenumber-domain average, and the dynamic solution
(the wave basis) at a low frequency against it."""
import math
import unittest

import numpy as np

import support
from green_soil import greens, responses as R, spectral

FP = R.Footprint(0.6, 1.3)


def wavenumber_average(layers, dx, dy, a, b, k_top=None, n_k=400, n_theta=800):
    """(1/4 pi^2) int int (G - G_s)(|k|) S(kx, ky) e^{i k.d} d^2k for two
    a x b footprints offset by (dx, dy), S the product of their transforms
    (sinc^2 each way), by Gauss-Legendre in polar coordinates: no radial
    grid, splines, tents or tail."""
    k_top = k_top or 40.0 / layers[0].thickness
    xk, wk = np.polynomial.legendre.leggauss(n_k)
    k = 0.5 * k_top * (xk + 1.0)
    wk = 0.5 * k_top * wk
    xt, wt = np.polynomial.legendre.leggauss(n_theta)
    th = math.pi * (xt + 1.0)
    wt = math.pi * wt
    diff = spectral.surface_flexibility(layers, k, 0.0) - spectral.top_static(layers) / k
    kx = np.outer(k, np.cos(th))
    ky = np.outer(k, np.sin(th))
    s = np.sinc(kx * a / (2 * math.pi)) ** 2 * np.sinc(ky * b / (2 * math.pi)) ** 2
    angular = (s * np.cos(kx * dx + ky * dy)) @ wt
    return float(np.real(wk @ (k * diff * angular))) / (4.0 * math.pi**2)


class Static(unittest.TestCase):
    def test_boussinesq_square_mean(self):
        # Mean displacement of a flexible B x B square under a uniform
        # pressure: F I (1 - nu)/(2 mu B), I = (4/pi)(ln(1 + sqrt 2) - (sqrt 2 - 1)/3).
        i = (4.0 / math.pi) * (math.log(1.0 + math.sqrt(2.0)) - (math.sqrt(2.0) - 1.0) / 3.0)
        for b in (0.5, 2.0):
            self.assertAlmostEqual(greens.static_pair(0.0, 0.0, b, b) * 2.0 * b / i, 1.0, delta=1e-10)

    def test_boussinesq_rectangle_corner(self):
        # Love (1929): the corner of a uniformly loaded a x b rectangle sinks
        # p (1 - nu)/(2 pi mu) (a ln((b + d)/a) + b ln((a + d)/b)), d its diagonal.
        a, b = FP.along, FP.across
        d = math.hypot(a, b)
        love = (a * math.log((b + d) / a) + b * math.log((a + d) / b)) / (2.0 * math.pi * a * b)
        self.assertAlmostEqual(greens.static_point(0.5 * a, 0.5 * b, a, b) / love, 1.0, delta=1e-10)
        self.assertAlmostEqual(greens.static_point(-0.5 * a, 0.5 * b, a, b) / love, 1.0, delta=1e-10)

    def test_layered_static_through_space_against_wavenumber_average(self):
        layers = support.elastic(support.LAYERED)
        top = spectral.top_static(layers)
        pairs, _ = R.spectra(layers, FP, [(0.0, 0.0), (0.6, 1.3), (3.0, 0.0)], [], [0.0])
        for (dx, dy), value in zip([(0.0, 0.0), (0.6, 1.3), (3.0, 0.0)], pairs[:, 0]):
            ref = greens.static_pair(dx, dy, FP.along, FP.across) * top + wavenumber_average(
                layers, dx, dy, FP.along, FP.across)
            self.assertLess(abs(value / ref - 1.0), 3e-5, "offset (%g, %g)" % (dx, dy))
            # The layers below make the ground stiffer than the top layer alone.
            self.assertLess(value.real, greens.static_pair(dx, dy, FP.along, FP.across) * top)

    def test_dynamic_solution_tends_to_the_static_one(self):
        # The wave basis at 1e-3 Hz against the static (Papkovich-Neuber)
        # basis. Measured: 2e-6 (the footprint itself) to 1.4e-4 (3 m, where
        # the two rectangles' static values nearly cancel the smooth part's);
        # at 1e-2 Hz 2e-5 to 9e-4, the radiation term i w r / c growing.
        layers = support.elastic(support.LAYERED)
        offsets = [(0.0, 0.0), (0.6, 1.3), (3.0, 0.0)]
        pairs, _ = R.spectra(layers, FP, offsets, [], [0.0, 2.0 * math.pi * 1e-3 - 1e-6j])
        for (dx, dy), value in zip(offsets, pairs):
            self.assertLess(abs(value[1] / value[0] - 1.0), 3e-4, "offset (%g, %g)" % (dx, dy))


if __name__ == "__main__":
    unittest.main()
