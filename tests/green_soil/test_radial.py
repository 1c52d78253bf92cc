"""The surface's radial displacement under a vertical point load
(green_soil/radial.py): its wavenumber kernel against Lamb's closed form
for a homogeneous half-space, the static limit against Boussinesq's radial
displacement -(1 - 2 nu)/(4 pi mu r) (a half-space, and three equal layers
condensed onto the surface), the low-frequency limit tending to it, the
transform against an independent quadrature of the closed-form kernel, and
the closed-form J1 tail against a quadrature. fe_soil/lamb.py has no
horizontal component of Pekeris' solution, so the static limit stands for
it."""
import math
import unittest

import numpy as np
from scipy import special

import support
from green_soil import radial
from fe_soil.params import Layer

MU = support.HALF_SPACE[0].shear_modulus


def boussinesq(r, nu=0.25, mu=MU):
    return -(1.0 - 2.0 * nu) / (4.0 * math.pi * mu * np.asarray(r))


def lamb_kernel(layer, k, w):
    """H(k, w) of a homogeneous half-space in closed form: k (2 k^2 - k_s^2 -
    2 nu_P nu_S) / (mu F), F = (2 k^2 - k_s^2)^2 - 4 k^2 nu_P nu_S."""
    from green_soil.spectral import moduli

    mu, lam, rho = moduli(layer, w)
    ks2, kp2 = w * w * rho / mu, w * w * rho / (lam + 2.0 * mu)

    def root(x):
        s = np.sqrt(x + 0j)
        return np.where(s.real < 0, -s, s)

    vp, vs = root(k * k - kp2), root(k * k - ks2)
    f = (2.0 * k * k - ks2) ** 2 - 4.0 * k * k * vp * vs
    return k * (2.0 * k * k - ks2 - 2.0 * vp * vs) / (mu * f)


class Radial(unittest.TestCase):
    def test_kernel_is_lambs(self):
        layer = Layer(1.0, 1800.0, 200.0, 0.25, 0.02)
        k = np.array([0.05, 0.2, 0.5, 0.62, 0.8, 2.0, 10.0])
        for w in (2 * math.pi * 20.0, 2 * math.pi * 20.0 - 1.5j, 2 * math.pi * 3.0):
            got = radial.radial_flexibility([layer], k, w)
            exact = lamb_kernel(layer, k, w)
            self.assertLess(np.abs(got / exact - 1).max(), 1e-9, w)

    def test_static_limit_is_boussinesq(self):
        r = np.array([0.5, 2.0, 8.0, 32.0, 64.0])
        half = radial.point(support.HALF_SPACE, [0.0], r)[:, 0]
        self.assertLess(np.abs(half / boussinesq(r) - 1).max(), 1e-12)
        # The same ground as three equal layers over a half-space: the
        # condensation, the k = 0 extrapolation, J1 and the tail at work.
        stack = [Layer(1.5, 1800.0, 200.0, 0.25, 0.0)] * 4
        layered = radial.point(stack, [0.0], r)[:, 0]
        self.assertLess(np.abs(layered / boussinesq(r) - 1).max(), 1e-9)
        self.assertLess(np.abs(layered.imag).max(), 1e-12 * np.abs(boussinesq(r)).max())

    def test_low_frequencies_tend_to_boussinesq(self):
        r = np.array([2.0, 4.0, 8.0])
        err = [np.abs(radial.point(support.HALF_SPACE, [2 * math.pi * f], r)[:, 0]
                      / boussinesq(r) - 1) for f in (0.2, 0.05)]
        self.assertLess(err[1].max(), 1e-3)  # k_s r = 0.013 at 8 m
        self.assertTrue((err[1] < err[0]).all(), err)

    def test_transform_against_an_independent_quadrature(self):
        layer = Layer(1.0, 1800.0, 200.0, 0.25, 0.02)
        w = 2 * math.pi * 20.0
        r = np.array([8.0, 16.0])
        got = radial.point([layer], [w], r)[:, 0]
        from green_soil.spectral import moduli

        top = -(1.0 - 2.0 * layer.poisson) / (2.0 * moduli(layer, w)[0])
        k = np.arange(5e-5, 60.0, 1e-4)  # uniform, far past the pole and the branch points
        f = k * lamb_kernel(layer, k, w) - top
        for ri, g in zip(r, got):
            exact = np.trapz(f * special.j1(k * ri), k) / (2 * math.pi) + top / (2 * math.pi * ri)
            self.assertLess(abs(g / exact - 1), 2e-3, ri)

    def test_far_field_is_the_rayleigh_waves_ratio(self):
        # Far from the load the Rayleigh wave dominates both components:
        # u_r / u_z -> -i (H/V) H1(k_R r) / H0(k_R r) (Hankel functions of
        # the second kind), H/V = (1 + s^2 - 2 q s) / (q (1 - s^2)), q and s
        # = sqrt(1 - c_R^2 / c^2) with c the P and the S speed (0.6813 at
        # nu = 1/4). Nearer, the P wave along the surface beats with it.
        from green_soil import greens, spectral
        from fe_soil.params import rayleigh_speed

        layer = Layer(1.0, 1800.0, 200.0, 0.25, 0.002)
        w = 2 * math.pi * 20.0
        cr = rayleigh_speed(layer.shear_speed, layer.poisson)
        q = math.sqrt(1 - (cr / layer.p_speed) ** 2)
        s = math.sqrt(1 - (cr / layer.shear_speed) ** 2)
        hv = (1 + s * s - 2 * q * s) / (q * (1 - s * s))
        r = np.arange(1024.0, 1044.0, 2.0)  # a beat length of the P and Rayleigh waves
        ur = radial.point([layer], [w], r)[:, 0]
        mu = spectral.moduli(layer, w)[0]
        uz = (greens.smooth_part([layer], [w], r, greens.Discretisation())[:, 0]
              + (1 - layer.poisson) / (2 * math.pi * mu * r))
        x = w / cr * r
        ratio = ur / uz / (special.hankel2(1, x) / special.hankel2(0, x))
        self.assertAlmostEqual(hv, 0.6813, delta=1e-4)
        # In phase with H1/H0 and of the opposite sign: u_r points back to
        # the load when u_z is down (as Boussinesq's static radial value).
        err = np.abs(ratio / -hv - 1).max()
        self.assertLess(err, 0.01, ratio)  # measured 0.0058

    def test_footprint_means_at_low_frequency(self):
        # A unit force spread over a 1 m square: the x and y displacement at
        # points beside it, at 0.05 Hz (elastic), against Boussinesq's
        # radial displacement averaged over the square (midpoint rule).
        from green_soil.responses import Footprint

        n = 300
        s = (np.arange(n) + 0.5) / n - 0.5
        gx, gy = (g.ravel() for g in np.meshgrid(s, s, indexing="ij"))
        offsets = [(3.0, 4.0), (-6.0, 8.0), (0.0, 10.0)]
        got = radial.point_means(support.HALF_SPACE, Footprint(1.0, 1.0), offsets,
                                 [2 * math.pi * 0.05])[:, :, 0]
        for i, (dx, dy) in enumerate(offsets):
            ex, ey = dx - gx, dy - gy
            rho = np.hypot(ex, ey)
            ur = boussinesq(rho) / (n * n)
            exact = np.array([np.sum(ur * ex / rho), np.sum(ur * ey / rho)])
            scale = np.hypot(*exact)
            self.assertLess(np.abs(got[:, i] - exact).max(), 2e-3 * scale, (offsets[i], got[:, i],
                                                                           exact))

    def test_j1_tail(self):
        for r, K in ((0.5, 5.0), (2.0, 5.0), (8.0, 1.0)):
            x = np.linspace(K, 4000.0, 2_000_001)
            exact = np.trapz(special.j1(x * r) / x ** 2, x)
            self.assertAlmostEqual(radial.tail_integral_j1(np.array([r]), K)[0] / exact, 1.0,
                                   delta=1e-5)  # the quadrature: to 2e-6


if __name__ == "__main__":
    unittest.main()
