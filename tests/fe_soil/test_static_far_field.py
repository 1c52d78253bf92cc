"""The FE soil's static far field: a footprint's static displacement on the
homogeneous half-space at 4 and 8 m against Boussinesq's closed form on the
block the scene keys give (the default static extension), on the layered
soil against the fine extension's far field, the static state
at rest when stepped on the block with the correction added, and the parts
of the correction: the coarse block's node planes, their interpolation,
the coarse operators' size."""
import math
import unittest
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE

from fe_soil import config, far_field
from fe_soil.footprints import hat_values
from fe_soil.model import FESoil

F = 1e4  # N on the middle footprint


def boussinesq_mean(layer, force, receiver, fp, n=400):
    """Vertical surface displacement at `receiver` (outside the footprint)
    under `force` spread uniformly over the footprint: the point-load
    solution F (1 - nu)/(2 pi G r) averaged over the footprint (midpoint rule,
    n x n points; 1e-6 relative at 4 m)."""
    g = (np.arange(n) + 0.5) / n - 0.5
    X, Y = np.meshgrid(fp.x + fp.along * g, fp.y + fp.across * g)
    r = np.hypot(X - receiver[0], Y - receiver[1])
    return force * (1.0 - layer.poisson) / (2.0 * math.pi * layer.shear_modulus) * np.mean(1.0 / r)


def block(static_reach=None):
    """The scene's table on the homogeneous half-space at f_max 10 Hz (h =
    0.77 m, 37,179 DOFs), 21 sleepers of 0.25 x 2.5 m at 0.6 m, receivers at 4 and 8 m."""
    table = {"model": "fe", "f_max": 10.0, "growth": 1.25, "receivers": [4.0, 8.0],
             "layers": [{"density": HALF_SPACE.density, "shear_wave_speed": HALF_SPACE.shear_speed,
                         "poisson": HALF_SPACE.poisson}]}
    if static_reach is not None:
        table["static_reach"] = static_reach
    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0) for i in range(21)]
    return config.block_params(config.parse(table), sleepers)[0]


def surface_uz(soil, x, y):
    """Downward displacement of the Q1 field at a surface point."""
    i, j = soil._surface_index
    on = np.flatnonzero(i >= 0)
    w = hat_values(soil.nodes[0], x)[i[on]] * hat_values(soil.nodes[1], y)[j[on]]
    return -soil.comm.allreduce(float(np.sum(w * soil.u[3 * on + 2])))


class StaticFarField(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.p = block()
        cls.soil = FESoil(cls.p)
        cls.forces = np.zeros(21)
        cls.forces[10] = F
        cls.w0 = cls.soil.statics(cls.forces)

    def test_displacement_at_4_and_8_m_within_3_percent_of_boussinesq(self):
        # Measured: 1.003 at 4 m and 1.007 at 8 m (1.002, 0.999 at 10
        # elements per wavelength; 0.998, 0.998 before fine_depth); the block
        # with its springs alone (static_reach = 0): 1.068 and 1.112 (1.071
        # and 1.112 at 10).
        fp = self.p.footprints[10]
        for x, y in self.p.receivers:
            ratio = surface_uz(self.soil, x, y) / boussinesq_mean(HALF_SPACE, F, (x, y), fp)
            self.assertAlmostEqual(ratio, 1.0, delta=0.03, msg=f"at {y} m")

    def test_static_state_stays_at_rest_on_the_block(self):
        # The force of the soil outside the block is held in the dynamics:
        # without it the boundary springs alone would carry the static state.
        state = self.soil.save()
        H = 2.0 * self.soil.dt
        for k in range(20):
            w, v = self.soil.advance(k * H, H, self.forces, self.forces)
        np.testing.assert_allclose(w, self.w0, rtol=1e-6, atol=1e-9 * np.max(self.w0))
        self.assertLess(np.max(np.abs(v)), 1e-6 * np.max(self.w0) / H)
        self.soil.restore(state)

    def test_the_coarse_operators_are_smaller_than_the_block(self):
        # Measured: 1,440 and 8,580 DOFs against the block's 37,179 (at 10
        # elements per wavelength 1,440 and 7,410 against 25,875; before
        # fine_depth 1,080 and 5,700 against 11,250; the fine planes carried
        # through the extension gave 41,184).
        block_dofs, extended_dofs = self.soil._extension.dofs()
        self.assertEqual(block_dofs, 3 * 10 * 6 * 8)  # 6 z planes before fine_depth (18.4 m here)
        self.assertLess(extended_dofs, self.soil.global_dofs() / 1.5)

    def test_the_key_reaches_the_block(self):
        self.assertEqual(self.p.static_reach, 5.0)  # the default of [soil] static_reach
        self.assertEqual(block(0.0).static_reach, 0.0)
        with self.assertRaisesRegex(config.ConfigError, r"\[soil\] static_reach must be >= 0"):
            block(-1.0)


class LayeredFarField(unittest.TestCase):
    """The layers of scenes/ground_vibration.toml (1.4 m at c_S 128 m/s, 2.7 m
    at 176 m/s on 355 m/s): the far field the coarse correction gives against
    the one the block's own planes carried through the graded extension gave
    (the previous statics, measured on this block: 26.8 s of static solve).
    The block is the one the fixture was measured on: 10 elements per
    wavelength (the default before 12; at 12 the block's own planes differ,
    its springs alone give 1.045 / 1.440 of the fixture at 4 / 8 m against
    1.142 / 1.412, and the correction 0.886 / 0.964, with 24 coarse
    elements 0.895 / 0.987: the block's discretisation, not the coarse
    block's)."""

    EXTENDED = {4.0: 1.5991753e-06, 8.0: 4.7495341e-07}  # m down, 10 kN

    def test_displacement_at_4_and_8_m_within_2_percent_of_the_fine_extension(self):
        # Measured: 1.004 at 4 m and 0.999 at 8 m (12 coarse elements; 8
        # gave 0.978 at 4 m, fails); the block's springs alone 1.142 / 1.412.
        table = {"model": "fe", "f_max": 10.0, "growth": 1.25, "receivers": [4.0, 8.0],
                 "elements_per_wavelength": 10.0,
                 "layers": [{"thickness": 1.4, "density": 1800.0, "shear_wave_speed": 128.0,
                             "poisson": 0.375},
                            {"thickness": 2.7, "density": 1800.0, "shear_wave_speed": 176.0,
                             "poisson": 0.195},
                            {"density": 1800.0, "shear_wave_speed": 355.0, "poisson": 0.478}]}
        sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0) for i in range(21)]
        p = config.block_params(config.parse(table), sleepers)[0]
        soil = FESoil(p)
        forces = np.zeros(21)
        forces[10] = F
        soil.statics(forces)
        for x, y in p.receivers:
            self.assertAlmostEqual(surface_uz(soil, x, y) / self.EXTENDED[y], 1.0, delta=0.02,
                                   msg=f"at {y} m")


class CoarseGrid(unittest.TestCase):
    def test_coarse_planes_are_a_subset_spaced_h_apart(self):
        planes = [float(v) for v in range(11)]
        self.assertEqual(far_field.coarse_planes(planes, 3.0), [0.0, 3.0, 6.0, 10.0])
        self.assertEqual(far_field.coarse_planes(planes, 3.0, keep=[4.0]),
                         [0.0, 3.0, 4.0, 7.0, 10.0])
        self.assertEqual(far_field.coarse_planes(planes, 0.5), planes)
        graded = [0.0, 0.5, 1.0, 1.5, 2.5, 4.0, 6.0]
        self.assertEqual(far_field.coarse_planes(graded, 1.2), [0.0, 1.5, 4.0, 6.0])

    def test_the_layer_interfaces_stay_planes_of_the_coarse_block(self):
        table = {"model": "fe", "f_max": 10.0, "growth": 1.25, "receivers": [4.0, 8.0],
                 "layers": [{"thickness": 1.0, "density": 1800.0, "shear_wave_speed": 128.0,
                             "poisson": 0.375},
                            {"thickness": 2.0, "density": 1800.0, "shear_wave_speed": 176.0,
                             "poisson": 0.195},
                            {"density": 1800.0, "shear_wave_speed": 355.0, "poisson": 0.478}]}
        sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0) for i in range(21)]
        p = config.block_params(config.parse(table), sleepers)[0]
        xs, ys, zs = far_field.coarse_nodes(p, (p.x_nodes, p.y_nodes, p.z_nodes))
        for z in (-1.0, -3.0):  # -1 m falls between coarse planes unless kept
            self.assertTrue(any(abs(v - z) < 1e-9 for v in zs), f"{z} m not in {zs}")
        for coarse, fine in zip((xs, ys, zs), (p.x_nodes, p.y_nodes, p.z_nodes)):
            self.assertTrue(set(coarse) <= set(fine))
            self.assertEqual((coarse[0], coarse[-1]), (fine[0], fine[-1]))

    def test_trilinear_interpolation_is_exact_for_a_trilinear_field(self):
        nodes = ([0.0, 1.0, 3.0, 7.0], [0.0, 2.0, 2.5], [-5.0, -1.0, 0.0])
        f = lambda x, y, z: 1.0 + 2.0 * x - 3.0 * y + 0.5 * z + 0.25 * x * y * z
        grid = np.array([[[f(x, y, z) for z in nodes[2]] for y in nodes[1]] for x in nodes[0]])
        rng = np.random.default_rng(3)
        points = np.column_stack([rng.uniform(a[0], a[-1], 50) for a in nodes])
        points = np.vstack([points, [0.0, 0.0, -5.0], [7.0, 2.5, 0.0], [3.0, 2.0, -1.0]])
        index, weight = far_field.trilinear(nodes, points)
        np.testing.assert_allclose(np.sum(weight * grid.reshape(-1)[index], axis=1),
                                   f(*points.T), rtol=0.0, atol=1e-12)


if __name__ == "__main__":
    unittest.main()
