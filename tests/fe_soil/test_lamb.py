"""Lamb's problem: the closed form of Pekeris (1955) for the surface
displacement under a vertical point load (fe_soil/lamb.py) on its own, and
the finite-element soil's surface velocity under a Ricker force against it
at 4 and 8 m, on two meshes."""
import math
import unittest

import numpy as np

from support import HALF_SPACE, Footprint, SoilParams, graded_nodes

from fe_soil import lamb
from fe_soil.model import FESoil
from fe_soil.params import rayleigh_speed

MU, CS = HALF_SPACE.shear_modulus, HALF_SPACE.shear_speed


def cagniard_quadrature(tau, nodes=400):
    """w / (F/(pi mu r)) from the integral -(1/pi) int_a^tau p Im f(p) /
    sqrt(tau^2 - p^2) dp (fe_soil/lamb.py), by Gauss-Legendre in phi with
    p = tau sin(phi), split at p = 1: independent of the partial fractions."""
    a = math.sqrt(lamb.A2)

    def im_f(p):
        x = p * p
        d = (1.0 - 2.0 * x) ** 4 - 16.0 * x * x * (x - lamb.A2) * (x - 1.0)
        extra = np.where(x > 1.0, 4.0 * x * np.sqrt(np.maximum(x - lamb.A2, 0.0)) * np.sqrt(np.maximum(x - 1.0, 0.0)), 0.0)
        return np.sqrt(x - lamb.A2) * ((1.0 - 2.0 * x) ** 2 + extra) / d

    q, w = np.polynomial.legendre.leggauss(nodes)
    cuts = [math.asin(a / tau)] + ([math.asin(1.0 / tau)] if tau > 1.0 else []) + [0.5 * math.pi]
    total = 0.0
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        phi = lo + (hi - lo) * 0.5 * (q + 1.0)
        p = tau * np.sin(phi)
        total += 0.5 * (hi - lo) * float(np.sum(w * p * im_f(p)))
    return -total / math.pi


class ClosedForm(unittest.TestCase):
    def test_against_the_cagniard_integral(self):
        taus = [0.6, 0.7, 0.9, 0.99, 1.01, 1.04, 1.07, 1.085]
        got = lamb.normalized_step(np.array(taus))
        for tau, g in zip(taus, got):
            self.assertAlmostEqual(g, cagniard_quadrature(tau), delta=1e-6 * max(1.0, abs(g)), msg=f"tau = {tau}")

    def test_pekeris_explicit_form(self):
        # Pekeris' (1955) expressions for nu = 1/4 (module docstring).
        s3, g = math.sqrt(3.0), lamb.GAMMA2
        tau = np.linspace(1.0 / s3 + 1e-6, 1.0 - 1e-6, 200)
        first = (6.0 - s3 / np.sqrt(tau**2 - 0.25) + math.sqrt(3.0 * s3 - 5.0) / np.sqrt(tau**2 - (3.0 - s3) / 4.0)
                 - math.sqrt(3.0 * s3 + 5.0) / np.sqrt(g - tau**2)) / 32.0
        np.testing.assert_allclose(lamb.normalized_step(tau), first, rtol=0.0, atol=1e-12)
        self.assertTrue(np.all(first < 0.0))  # upward (against the load) before the S wave
        tau = np.linspace(1.0 + 1e-6, math.sqrt(g) - 1e-6, 200)
        second = (6.0 - math.sqrt(3.0 * s3 + 5.0) / np.sqrt(g - tau**2)) / 16.0
        np.testing.assert_allclose(lamb.normalized_step(tau), second, rtol=1e-12, atol=1e-12)

    def test_arrivals_and_late_limit(self):
        a, gamma = math.sqrt(lamb.A2), math.sqrt(lamb.GAMMA2)
        # The Rayleigh root: the same c_R as the Rayleigh equation gives.
        self.assertAlmostEqual(lamb.RAYLEIGH_RATIO, rayleigh_speed(1.0, 0.25) / 1.0, delta=1e-9)
        self.assertAlmostEqual(lamb.RAYLEIGH_RATIO, 0.919402, delta=1e-6)
        # Nothing before the P wave, continuous there and at the S wave.
        self.assertEqual(float(np.max(np.abs(lamb.normalized_step(np.linspace(0.0, a - 1e-9, 50))))), 0.0)
        self.assertLess(abs(lamb.normalized_step(np.array([a + 1e-9]))[0]), 1e-6)
        self.assertNotEqual(lamb.normalized_step(np.array([a + 1e-3]))[0], 0.0)
        near_s = lamb.normalized_step(np.array([1.0 - 1e-9, 1.0 + 1e-9]))
        self.assertAlmostEqual(near_s[0], near_s[1], delta=1e-6)
        # Just before the Rayleigh arrival an inverse square-root singularity
        # (upward, against the load): w sqrt(gamma - tau) tends to a constant.
        eps = np.array([1e-6, 1e-8, 1e-10])
        scaled = lamb.normalized_step(gamma - eps) * np.sqrt(eps)
        self.assertLess(scaled[0], 0.0)
        self.assertAlmostEqual(scaled[2] / scaled[1], 1.0, delta=1e-3)
        # From the Rayleigh arrival on: Boussinesq's F (1 - nu)/(2 pi mu r).
        r = 8.0
        late = lamb.step_response(np.array([1.0001, 1.5, 10.0, 1e4]) * gamma * r / CS, r, MU, CS, 1e5)
        np.testing.assert_allclose(late, lamb.static_displacement(r, MU, 1e5), rtol=1e-12)
        self.assertAlmostEqual(lamb.static_displacement(r, MU, 1e5), 3e5 / (8.0 * math.pi * MU * r), delta=1e-20)

    def test_convolution(self):
        # A smooth step (rise 0.2 s) ends at the static value; the velocity
        # (F'' convolved) is the derivative of the displacement (F').
        r, rise = 6.0, 0.2
        f = lambda t: 0.5 * (1.0 + np.tanh((t - 0.3) / (0.25 * rise)))  # noqa: E731
        df = lambda t: 0.5 / (0.25 * rise) / np.cosh((t - 0.3) / (0.25 * rise)) ** 2  # noqa: E731
        end = lamb.convolve(np.array([1.5]), r, MU, CS, f, df)[0]
        self.assertAlmostEqual(end / lamb.static_displacement(r, MU), 1.0, delta=1e-9)
        fr, dfr, d2fr = lamb.ricker(8.0, 0.15)
        t = np.linspace(0.0, 0.4, 4001)
        u = lamb.convolve(t, r, MU, CS, fr, dfr)
        v = lamb.convolve(t, r, MU, CS, dfr, d2fr)
        self.assertLess(np.max(np.abs(np.gradient(u, t) - v)), 1e-4 * np.max(np.abs(v)))


# The FE comparison. A Ricker force (centre 8 Hz, peak at t0 = 0.15 s,
# significant content to 20 Hz: 11.5 elements per Rayleigh wavelength at
# h = 0.4 m) on a 0.4 m square footprint at the centre of the axis of a
# 32 x 22 x 16 m half block (nu = 1/4, c_S = 100 m/s, no damping); h in
# 4 m along x, 10 m across and 5 m down from the footprint, growing by 1.2
# beyond. Receivers at 4 and 8 m across; they record velocity, compared as
# such (v = g * F'', g the step response). The reference includes the
# footprint (the point response averaged over the square, 6 x 6 Gauss
# points): a point load instead changes the peak by 0.5 % at 4 and 8 m.
FC, T0, FOOT = 8.0, 0.15, 0.4
BLOCK = (32.0, 22.0, 16.0)
DISTANCES = (4.0, 8.0)


def window_end(r):
    """The pulse's onset (t0 - 1/fc: the Ricker is below 1e-3 of its peak
    before) plus the shortest shear-wave path source -> boundary ->
    receiver: the first wave reflected by the block that can be back."""
    L, W, D = BLOCK
    paths = [2.0 * math.hypot(D, r / 2.0), 2.0 * W - r, 2.0 * math.hypot(L / 2.0, r / 2.0)]
    return T0 - 1.0 / FC + min(paths) / CS


def run_block(h):
    L, W, D = BLOCK
    p = SoilParams(
        length=L, half_width=W, depth=D, layers=[HALF_SPACE],
        footprints=[Footprint(L / 2.0, FOOT, FOOT)], receivers=[(L / 2.0, y) for y in DISTANCES],
        x_nodes=graded_nodes(0.0, L, L / 2.0, h, 4.0, 1.2),
        y_nodes=graded_nodes(0.0, W, 0.0, h, 10.0, 1.2),
        z_nodes=graded_nodes(-D, 0.0, 0.0, h, 5.0, 1.2))
    soil = FESoil(p)
    f = lamb.ricker(FC, T0)[0]
    H = soil.dt
    for k in range(int(window_end(max(DISTANCES)) / H) + 1):
        soil.advance(k * H, H, [f(k * H)], [f((k + 1) * H)])
    t, v = soil.receiver_series()
    return t, -v[:, :, 2]  # downward, as the load


def reference(t, r, gauss=6):
    _, df, d2f = lamb.ricker(FC, T0)
    q, w = np.polynomial.legendre.leggauss(gauss)
    q, w = 0.5 * FOOT * q, 0.5 * w
    return sum(wx * wy * lamb.convolve(t, math.hypot(qx, r - qy), MU, CS, df, d2f)
               for qx, wx in zip(q, w) for qy, wy in zip(q, w))


def peak(t, x):
    """(time, value) of the maximum, by a parabola through the top three."""
    k = int(np.argmax(x))
    y0, y1, y2 = x[k - 1], x[k], x[k + 1]
    s = 0.5 * (y0 - y2) / (y0 - 2.0 * y1 + y2)
    return t[k] + s * (t[1] - t[0]), y1 - 0.25 * (y0 - y2) * s


def dispersion_estimate(t, ref, r, h):
    """The relative L2 error a phase error alone would make: lumped linear
    elements make a wave of wavenumber k slow by (k h)^2/24 (1D), a phase
    error phi(f) = k r (k h)^2 / 24 at the Rayleigh speed after r metres;
    weighted by the reference's spectrum (below 5 fc)."""
    n = 8 * len(t)
    spec = np.abs(np.fft.rfft(ref, n)) ** 2
    f = np.fft.rfftfreq(n, t[1] - t[0])
    keep = f < 5.0 * FC
    k = 2.0 * math.pi * f[keep] / rayleigh_speed(CS, HALF_SPACE.poisson)
    phi = k * r * (k * h) ** 2 / 24.0
    return math.sqrt(np.sum(spec[keep] * phi**2) / np.sum(spec[keep]))


class AgainstFE(unittest.TestCase):
    def test_surface_velocity_against_pekeris(self):
        # Measured at 4 / 8 m, h = 0.4 m (0.8 m): delay of the peak after
        # t0 +0.85 % / +0.31 % (+4.4 % / +1.9 %); peak +0.93 % / +0.44 %
        # (+5.7 % / +4.6 %); relative L2 over the window 1.86 % / 2.06 %
        # (9.0 % / 9.2 %) against a dispersion estimate of 1.5 % / 3.2 %
        # (6.1 % / 13 %). At 8 m and h = 0.4 m about half of the L2 is the
        # block's (P waves back from its boundary; a 48 x 34 x 28 m block:
        # 1.45 %). Fails with the mass 10 % large (L2 17 % at 4 m) or the
        # axis footprint's share 0.55 instead of 0.5 (L2 11 %).
        errors = {}
        for h in (0.4, 0.8):
            t, v = run_block(h)
            for i, r in enumerate(DISTANCES):
                inside = t <= window_end(r)
                ti, vi = t[inside], v[inside, i]
                ref = reference(ti, r)
                t_fe, p_fe = peak(ti, vi)
                t_ref, p_ref = peak(ti, ref)
                l2 = float(np.linalg.norm(vi - ref) / np.linalg.norm(ref))
                bound = 2.0 * dispersion_estimate(ti, ref, r, h)
                errors[h, r] = l2
                print(f"h = {h} m, r = {r} m: delay {t_fe - T0:.5f} s (closed form {t_ref - T0:.5f}), "
                      f"peak {p_fe:.4e} ({p_fe / p_ref - 1.0:+.2%}), L2 {l2:.2%} (bound {bound:.2%})")
                self.assertLess(l2, bound, msg=f"h {h}, r {r}")
                if h == 0.4:  # 11.5 elements per wavelength at 20 Hz (the rule: 12)
                    # The arrival: the Rayleigh pulse's peak after the force's.
                    self.assertAlmostEqual((t_fe - T0) / (t_ref - T0), 1.0, delta=0.03, msg=f"r {r}")
                    self.assertAlmostEqual(p_fe / p_ref, 1.0, delta=0.03, msg=f"r {r}")
        for r in DISTANCES:  # the error falls with h, about as h^2
            self.assertGreater(errors[0.8, r], 2.5 * errors[0.4, r], msg=f"r {r}: {errors}")


if __name__ == "__main__":
    unittest.main()
