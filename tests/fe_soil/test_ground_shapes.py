"""Ground shapes in the FE soil (fe_soil/ground_shapes.py): the cells an
embankment or a cutting takes out are exactly those outside its
cross-section at their midpoints (and the embankment's cells carry its
material), no midpoint lies on a slope, a slope has one step per element
row; the footprints load the crest or the cutting's base; receivers stand
on the meshed surface (on flat parts at the shape's own height, on a
slope within one step of it); each refusal names its key."""
import unittest
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE  # noqa: F401  (skips without dolfinx)

import dolfinx.mesh
from fe_soil import config, ground_shapes
from fe_soil.model import FESoil

LAYER = {"density": 1800.0, "shear_wave_speed": 128.0, "poisson": 0.375, "damping": 0.04}
SLEEPERS = [SimpleNamespace(x=0.6 * i, length=0.25, width=1.3, y=0.65) for i in range(21)]
BANK = {"name": "bank", "shape": "embankment", "height": 2.0, "crest_width": 4.0, "slope": 1.5,
        "shear_wave_speed": 200.0, "poisson": 0.3, "density": 1900.0, "damping": 0.05}
CUT = {"name": "cut", "shape": "cutting", "depth": 2.0, "base_width": 4.0, "slope": 1.5}
# on the crest or base, on the slope, at the toe or top edge, beyond
RECEIVERS = [1.0, 3.5, 5.0, 9.0]


def table(grounds, ground, **keys):
    t = {"model": "fe", "mesh_size": 1.0, "depth": 8.0, "margin": 4.0, "receivers": RECEIVERS,
         "static_reach": 0.0, "footprint_compliance": False, "layers": [dict(LAYER)],
         "grounds": grounds, "ground": ground}
    t.update(keys)
    return {k: v for k, v in t.items() if v is not None}


def block(grounds, ground, **keys):
    cfg = config.parse(table(grounds, ground, **keys))
    return config.block_params(cfg, SLEEPERS)[0]


def cell_values(soil, name):
    f = soil.fields[name]
    n = soil.mesh.topology.index_map(3).size_local
    return f.x.array[f.function_space.dofmap.list.array.reshape(-1)[:n]]


def outside(spec, y, z):
    """The cross-section's complement in closed form."""
    y = np.abs(y)
    if spec["shape"] == "embankment":
        return (z > 0.0) & (y > 0.5 * spec["crest_width"] + spec["slope"] * (spec["height"] - z))
    d = spec["depth"]
    return (z > -d) & (y < 0.5 * spec["base_width"] + spec["slope"] * (z + d))


class Geometry(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.soils = {s["name"]: FESoil(block([BANK, CUT], s["name"])) for s in (BANK, CUT)}

    def test_the_void_cells_are_those_outside_the_cross_section(self):
        for spec in (BANK, CUT):
            soil = self.soils[spec["name"]]
            n = soil.mesh.topology.index_map(3).size_local
            mid = dolfinx.mesh.compute_midpoints(soil.mesh, 3, np.arange(n, dtype=np.int32))
            void = outside(spec, mid[:, 1], mid[:, 2])
            self.assertGreater(void.sum(), 0)
            np.testing.assert_array_equal(cell_values(soil, "rho") == 0.0, void)
            np.testing.assert_array_equal(cell_values(soil, "mu") == 0.0, void)
            # no midpoint on the slope: at least a tenth of a cell from it
            edge = 0.5 * spec.get("crest_width", spec.get("base_width"))
            rise = spec.get("height", spec.get("depth"))
            zz = spec["height"] - mid[:, 2] if spec["shape"] == "embankment" else mid[:, 2] + rise
            on_slope = (zz >= 0.0) & (zz <= rise)
            gap = np.abs(np.abs(mid[:, 1]) - edge - spec["slope"] * zz)[on_slope]
            self.assertGreater(gap.min(), 0.1 * 1.0 * spec["slope"] / 2.0)
            # one step per element row between z = 0 (-depth) and the crest (0)
            zs = np.asarray(soil.nodes[2])
            rows = np.sum((zs > -1e-9) if spec["shape"] == "embankment" else
                          (zs > -rise - 1e-9) & (zs < 1e-9)) - 1
            ys = np.asarray(soil.nodes[1])
            cols = ys[(ys > edge - 1e-9) & (ys < edge + spec["slope"] * rise + 1e-9)]
            tops = {ground_shapes.surface_z(soil.p.ground, soil.nodes, 0.5 * (a + b))
                    for a, b in zip(cols[:-1], cols[1:])}
            self.assertEqual(len(tops), rows + 1)
        bank = self.soils["bank"]
        n = bank.mesh.topology.index_map(3).size_local
        mid = dolfinx.mesh.compute_midpoints(bank.mesh, 3, np.arange(n, dtype=np.int32))
        fill = (mid[:, 2] > 0.0) & ~outside(BANK, mid[:, 1], mid[:, 2])
        self.assertGreater(fill.sum(), 0)
        np.testing.assert_array_equal(cell_values(bank, "rho")[fill], BANK["density"])
        np.testing.assert_allclose(cell_values(bank, "cs")[fill], BANK["shear_wave_speed"])
        np.testing.assert_array_equal(cell_values(bank, "xi")[fill], BANK["damping"])

    def test_footprints_load_the_crest_or_the_base(self):
        for spec, z in ((BANK, BANK["height"]), (CUT, -CUT["depth"])):
            soil = self.soils[spec["name"]]
            c = soil.dof_coordinates()[soil.fp_idx]
            self.assertGreater(len(c), 0)
            np.testing.assert_allclose(c[:, 2], z, atol=1e-12)
            self.assertTrue(np.all(soil.fp_val < 0.0))
            # every footprint's load sums to its area (no share lost to voids)
            np.testing.assert_allclose(np.bincount(soil.fp_of, weights=-soil.fp_val),
                                       soil.fp_area, rtol=1e-12)

    def test_receivers_stand_on_the_surface(self):
        for spec, crest, toe in ((BANK, 2.0, 0.0), (CUT, -2.0, 0.0)):
            soil = self.soils[spec["name"]]
            z = soil.rec_points[:, 2]
            self.assertEqual(z[0], crest)  # on the crest or the base
            self.assertEqual(z[2], toe)  # at the toe or the top edge
            self.assertEqual(z[3], 0.0)  # beyond: the ground around
            true = (2.0 - (3.5 - 2.0) / 1.5) if spec is BANK else (-2.0 + (3.5 - 2.0) / 1.5)
            self.assertLessEqual(abs(z[1] - true), 1.0 + 1e-12)  # within a step of the slope
            self.assertIn(round(z[1], 9), {round(float(q), 9) for q in soil.nodes[2]})
            # the four nodes each receiver reads are soil nodes (none held)
            self.assertTrue(np.all(soil.mask[soil.rec_idx] > 0.0))
            np.testing.assert_allclose(np.bincount(soil.rec_of, weights=soil.rec_w), 1.0)

    def test_statics_hold_the_voids_at_zero(self):
        for soil in self.soils.values():
            w = soil.statics(np.full(len(SLEEPERS), 1e4))
            self.assertTrue(np.all(w > 0.0))
            held = float(np.abs(soil.u[soil.mask == 0.0]).max())
            self.assertLess(held, 1e-12 * float(np.abs(soil.u).max()))


class Refusals(unittest.TestCase):
    def refused(self, pattern, grounds, ground, **keys):
        with self.assertRaisesRegex(config.ConfigError, pattern):
            block(grounds, ground, **keys)

    def test_each_refusal_names_its_key(self):
        for key in ("height", "crest_width", "slope"):
            self.refused(r"\[soil\] grounds\[1\]\.%s must be" % key,
                         [dict(BANK, **{key: -1.0})], "bank")
        for key in ("depth", "base_width"):
            self.refused(r"\[soil\] grounds\[1\]\.%s must be > 0" % key,
                         [dict(CUT, **{key: 0.0})], "cut")
        self.refused(r"\[soil\] grounds\[1\]\.heigth is not a key", [dict(BANK, heigth=1.0)],
                     "bank")
        self.refused(r"\[soil\] grounds\[1\]\.shear_wave_speed is not a key",
                     [dict(CUT, shear_wave_speed=100.0)], "cut")
        self.refused(r"\[soil\] grounds\[1\]\.shape must be one of", [dict(CUT, shape="hill")],
                     "cut")
        self.refused(r"\[soil\] grounds\[1\]\.shear_wave_speed is missing",
                     [{k: v for k, v in BANK.items() if k != "shear_wave_speed"}], "bank")
        self.refused(r"\[soil\] ground must be 'at_grade' or the name", [CUT], "cutt")
        self.refused(r"\[soil\] grounds\[2\]\.name 'cut' repeats grounds\[1\]", [CUT, CUT], "cut")
        self.refused(r"\[soil\] grounds\[1\]\.slope: the embankment reaches 32 m",
                     [dict(BANK, slope=15.0)], "bank")
        self.refused(r"\[soil\] grounds\[1\]\.depth 8 m: the cutting must end above",
                     [dict(CUT, depth=8.0, slope=0.5)], "cut")
        self.refused(r"\[soil\] grounds\[1\]\.crest_width 2 m: the track's footprints reach 1\.3 m",
                     [dict(BANK, crest_width=2.0)], "bank")
        self.refused(r"\[soil\] grounds\[1\]\.base_width 2 m", [dict(CUT, base_width=2.0)], "cut")
        self.refused(r"\[soil\] static_reach: the FE soil's static far field assumes a flat",
                     [CUT], "cut", static_reach=5.0)
        self.refused(r"\[soil\] footprint_compliance: .* assumes a flat ground",
                     [BANK], "bank", footprint_compliance=True)
        trench = {"name": "t", "kind": "trench", "distance": 4.0, "depth": 1.0, "width": 0.5,
                  "length": 4.0}
        self.refused(r"\[soil\] measures: 't' begins 4 m from the track, inside the cutting",
                     [CUT], "cut", measures=[trench], receivers=[1.0, 9.0])


if __name__ == "__main__":
    unittest.main(argv=__import__("sys").argv[:1])
