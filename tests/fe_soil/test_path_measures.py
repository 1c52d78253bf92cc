"""Path measures in the FE soil (fe_soil/path_measures.py): the keys of
[[soil.measures]] and each refusal naming its key, the node planes that
resolve a measure, and the cells an open trench takes out and a wall or an
in-fill takes over: exactly those inside the box; the static state with
a trench at rest."""
import math
import unittest
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE

import dolfinx.mesh
from fe_soil import config, path_measures
from fe_soil.model import FESoil
from fe_soil.params import rayleigh_speed

LAYER = {"density": HALF_SPACE.density, "shear_wave_speed": HALF_SPACE.shear_speed,
         "poisson": HALF_SPACE.poisson, "damping": 0.02}
SLEEPERS = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.6, y=0.0) for i in range(21)]
TRENCH = {"name": "open", "kind": "trench", "distance": 4.0, "depth": 3.0, "width": 1.5,
          "length": 6.0}
WALL = {"name": "wall", "kind": "wall", "distance": 6.5, "depth": 2.0, "width": 0.3,
        "length": 4.0, "x0": 7.0, "young_modulus": 30e9, "poisson": 0.2, "density": 2400.0,
        "damping": 0.02}
FOAM = {"name": "foam", "kind": "infilled_trench", "distance": 4.0, "depth": 2.0, "width": 1.0,
        "length": 6.0, "shear_wave_speed": 40.0, "poisson": 0.3, "density": 100.0}


def table(measures, **keys):
    t = {"model": "fe", "mesh_size": 1.0, "depth": 6.0, "margin": 3.0, "receivers": [2.0, 9.0],
         "static_reach": 0.0, "footprint_compliance": False, "layers": [dict(LAYER)],
         "measures": measures}
    t.update(keys)
    return {k: v for k, v in t.items() if v is not None}


def block(measures, **keys):
    cfg = config.parse(table(measures, **keys))
    return config.block_params(cfg, SLEEPERS)[0], cfg


def cell_midpoints(soil):
    n = soil.mesh.topology.index_map(3).size_local
    return dolfinx.mesh.compute_midpoints(soil.mesh, 3, np.arange(n, dtype=np.int32))


def cell_values(soil, name):
    f = soil.fields[name]
    n = soil.mesh.topology.index_map(3).size_local
    return f.x.array[f.function_space.dofmap.list.array.reshape(-1)[:n]]


def cell_volumes(soil, mid):
    """Volumes of the tensor grid's cells at their midpoints."""
    out = np.ones(len(mid))
    for axis, nodes in enumerate(soil.nodes):
        nodes = np.asarray(nodes)
        k = np.searchsorted(nodes, mid[:, axis]) - 1
        out *= nodes[k + 1] - nodes[k]
    return out


class Refusals(unittest.TestCase):
    def refused(self, pattern, measures, **keys):
        with self.assertRaisesRegex(config.ConfigError, pattern):
            block(measures, **keys)

    def test_each_refusal_names_its_key(self):
        self.refused(r"\[soil\] measures\[1\]\.kind must be one of", [{**TRENCH, "kind": "moat"}])
        self.refused(r"\[soil\] measures\[1\]\.density is not a key of a trench",
                     [{**TRENCH, "density": 1.0}])
        self.refused(r"\[soil\] measures\[2\]\.colour is not a key of a wall",
                     [TRENCH, {**WALL, "colour": 1}])
        for key in ("depth", "width", "length", "distance"):
            self.refused(r"\[soil\] measures\[1\]\.%s must be > 0 \(got 0\)" % key,
                         [{**TRENCH, key: 0.0}])
            self.refused(r"\[soil\] measures\[1\]\.%s must be > 0 \(got -1\)" % key,
                         [{**TRENCH, key: -1.0}])
        self.refused(r"\[soil\] measures\[1\]\.width 0\.01 m is below 0\.1 of the element size",
                     [{**TRENCH, "width": 0.01}])
        self.refused(r"\[soil\] measures\[1\]\.shear_wave_speed is missing",
                     [{k: v for k, v in FOAM.items() if k != "shear_wave_speed"}])
        self.refused(r"\[soil\] measures\[1\]\.young_modulus and shear_wave_speed both",
                     [{**FOAM, "young_modulus": 1e6}])
        self.refused(r"\[soil\] measures\[1\]\.poisson must be < 0\.5", [{**FOAM, "poisson": 0.5}])
        self.refused(r"\[soil\] measures\[2\]\.name 'open' repeats measures\[1\]",
                     [TRENCH, {**FOAM, "name": "open"}])
        self.refused(r"\[soil\] measures\[1\]\.name must be", [{**TRENCH, "name": "reference"}])
        self.refused(r"\[soil\] variant must be 'reference' or the name", [TRENCH],
                     variant="other")
        self.refused(r"\[soil\] measures must be a list", {"kind": "trench"})

    def test_placement_is_refused_where_it_does_not_fit(self):
        # the footprints reach 1.3 m from the axis; receivers at 2 and 9 m;
        # the block is 6 m deep and 9 + 3 m wide; the track spans 0-12.25 m
        # (the block from -3 to 15.25 m along the rail)
        self.refused(r"\[soil\] measures\[1\]\.distance 1 m: the trench overlaps the track's",
                     [{**TRENCH, "distance": 1.0}])
        self.refused(r"\[soil\] measures\[1\]\.distance: the trench .* holds the receiver at 9 m",
                     [{**TRENCH, "distance": 8.5}])
        self.refused(r"\[soil\] measures\[1\]\.depth: the trench .* must lie inside the block",
                     [{**TRENCH, "depth": 6.0}])
        self.refused(r"\[soil\] measures\[1\]\.distance: the trench .* must lie inside",
                     [{**TRENCH, "distance": 11.5}])
        self.refused(r"\[soil\] measures\[1\]\.x0: the trench .* must lie inside the block",
                     [{**TRENCH, "x0": 14.0}])
        self.refused(r"\[soil\] measures\[2\]\.distance: the infilled_trench overlaps 'open' "
                     r"\(measures\[1\]\.distance\)", [TRENCH, {**FOAM, "distance": 5.0}])
        block([TRENCH, {**FOAM, "distance": 5.5}])  # touching: taken
        # a graded block: the absorbing layers begin at resolve_to across
        self.refused(r"\[soil\] measures\[1\]\.distance: .* inside the region inside the absorbing",
                     [TRENCH], mesh_size=None, f_max=10.0, growth=1.1, resolve_to=4.5,
                     receivers=[2.0, 4.0])


class NodePlanes(unittest.TestCase):
    def test_refine_axis(self):
        xs = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
        out = path_measures.refine_axis(xs, 1.9, 2.5, 0.25)
        self.assertIn(1.9, out)
        self.assertIn(2.5, out)
        inner = [x for x in out if 1.9 <= x <= 2.5]
        self.assertTrue(max(np.diff(inner)) <= 0.25 + 1e-12, out)
        self.assertNotIn(2.0, out)  # 0.1 m from a face: dropped
        steps = np.diff(out)
        self.assertLessEqual(steps.max(), path_measures.GROWTH + 1e-12, out)  # grows by <= 1.25
        outer = [b - a for a, b in zip(out, out[1:]) if b <= 1.9 + 1e-12 or a >= 2.5 - 1e-12]
        self.assertGreaterEqual(min(outer), 0.45, out)
        # protected planes stay where they are
        self.assertIn(2.0, path_measures.refine_axis(xs, 1.9, 2.5, 0.25, protect=[2.0]))

    def test_a_measure_is_resolved(self):
        p, _ = block([WALL, FOAM])
        wall, foam = p.measures
        for m in (wall, foam):
            for nodes, lo, hi in ((p.x_nodes, m.x_lo, m.x_hi), (p.y_nodes, m.y_lo, m.y_hi),
                                  (p.z_nodes, m.z_lo, 0.0)):
                self.assertTrue(np.isclose(nodes, lo, atol=1e-12).any(), (m.name, lo))
                self.assertTrue(np.isclose(nodes, hi, atol=1e-12).any(), (m.name, hi))
        across = [b - a for a, b in zip(p.y_nodes, p.y_nodes[1:])
                  if a >= wall.y_lo - 1e-12 and b <= wall.y_hi + 1e-12]
        self.assertGreaterEqual(len(across), 2)  # a thin wall: at least two elements
        # the foam: h = 1 m scaled by its Rayleigh speed over the soil's
        h_foam = 1.0 * rayleigh_speed(40.0, 0.3) / rayleigh_speed(100.0, 0.25)
        for nodes, lo, hi in ((p.x_nodes, foam.x_lo, foam.x_hi), (p.y_nodes, foam.y_lo, foam.y_hi),
                              (p.z_nodes, foam.z_lo, 0.0)):
            inner = [b - a for a, b in zip(nodes, nodes[1:]) if a >= lo - 1e-12 and b <= hi + 1e-12]
            self.assertLessEqual(max(inner), h_foam + 1e-12)
        # at the f_max rule: c_R of the foam / (n f_max)
        p, cfg = block([FOAM], mesh_size=None, f_max=10.0)
        m = p.measures[0]
        inner = [b - a for a, b in zip(p.x_nodes, p.x_nodes[1:])
                 if a >= m.x_lo - 1e-12 and b <= m.x_hi + 1e-12]
        self.assertLessEqual(max(inner), rayleigh_speed(40.0, 0.3) / (12.0 * 10.0) + 1e-12)

    def test_variants(self):
        self.assertEqual([m.name for m in block([TRENCH, WALL])[0].measures], ["open", "wall"])
        self.assertEqual([m.name for m in block([TRENCH, WALL], variant="wall")[0].measures],
                         ["wall"])
        self.assertEqual(list(block([TRENCH, WALL], variant="reference")[0].measures), [])
        # every variant's mesh holds every listed measure's faces: one mesh
        planes = [block([TRENCH, WALL], variant=v)[0] for v in (None, "reference", "wall")]
        for p in planes[1:]:
            for axis in ("x_nodes", "y_nodes", "z_nodes"):
                self.assertEqual(getattr(p, axis), getattr(planes[0], axis), axis)
        # alternatives at one place (a shallow and a deep trench) may overlap
        # as variants; built together they are refused
        deep = {**TRENCH, "name": "deep", "depth": 4.5}
        self.assertEqual([m.name for m in block([TRENCH, deep], variant="deep")[0].measures],
                         ["deep"])
        self.assertTrue(np.isclose(block([TRENCH, deep], variant="open")[0].z_nodes, -4.5).any())
        with self.assertRaisesRegex(config.ConfigError, r"measures\[2\]\.distance: the trench "
                                    r"overlaps 'open'"):
            block([TRENCH, deep])

    def test_planes_closer_than_round_off_are_one(self):
        # a face at the surface beside a top plane a rounding below it
        out = path_measures.refine_axis([-2.0, -1.4, -0.7, -2e-16], -1.0, 0.0, 0.5)
        self.assertEqual(out[-1], 0.0)
        self.assertGreater(min(np.diff(out)), 0.1, out)
        # an in-fill 1 m deep on a 0.5 m mesh whose top layer is 1.4 m thick
        layers = [dict(LAYER, thickness=1.4), dict(LAYER)]
        p, _ = block([{**FOAM, "depth": 1.0, "shear_wave_speed": 100.0}], mesh_size=0.5,
                     layers=layers)
        self.assertGreater(min(np.diff(p.z_nodes)), 0.1, p.z_nodes)


class Cells(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.p = block([TRENCH, WALL])[0]
        cls.soil = FESoil(cls.p)
        cls.mid = cell_midpoints(cls.soil)

    def test_cells_taken_out_and_taken_over_are_those_in_the_box(self):
        rho, mu = cell_values(self.soil, "rho"), cell_values(self.soil, "mu")
        vol = cell_volumes(self.soil, self.mid)
        trench, wall = self.p.measures
        for m, value in ((trench, 0.0), (wall, 2400.0)):
            box = path_measures.inside(m, self.mid)
            np.testing.assert_array_equal(rho == value, box)
            # the cells fill the box: their volume is the box's
            self.assertAlmostEqual(vol[box].sum(), m.length * m.width * m.depth, delta=1e-9)
        self.assertTrue(np.all(mu[path_measures.inside(trench, self.mid)] == 0.0))
        e = mu[path_measures.inside(wall, self.mid)] * 2.0 * (1.0 + 0.2)
        np.testing.assert_allclose(e, 30e9, rtol=1e-12)
        other = ~(path_measures.inside(trench, self.mid) | path_measures.inside(wall, self.mid))
        np.testing.assert_array_equal(rho[other], HALF_SPACE.density)

    def test_the_nodes_inside_an_open_trench_are_held(self):
        # nodes strictly inside the trench's box (on no face) touch no soil:
        # their three DOFs held (mask 0); the face nodes keep their mass
        c = self.soil.dof_coordinates()
        m = self.p.measures[0]
        strict = ((c[:, 0] > m.x_lo + 1e-9) & (c[:, 0] < m.x_hi - 1e-9) & (c[:, 1] > m.y_lo + 1e-9)
                  & (c[:, 1] < m.y_hi - 1e-9) & (c[:, 2] > m.z_lo + 1e-9))
        self.assertGreater(int(strict.sum()), 0)
        self.assertTrue(np.all(self.soil.mask[strict] == 0.0))
        faces = path_measures.inside(SimpleNamespace(x_lo=m.x_lo - 1e-6, x_hi=m.x_hi + 1e-6,
                                                     y_lo=m.y_lo - 1e-6, y_hi=m.y_hi + 1e-6,
                                                     z_lo=m.z_lo - 1e-6), c) & ~strict
        self.assertTrue(np.all(self.soil.m[faces] > 0.0))
        # held: the trench's inner nodes and the symmetry plane's u_y only
        sym = (np.abs(c[:, 1]) < 1e-9) & (np.arange(len(c)) % 3 == 1)
        np.testing.assert_array_equal(self.soil.mask == 0.0, strict | sym)
        # the soil steps and stays finite; the held nodes do not move
        self.soil.statics(np.full(21, 1e4))
        for k in range(20):
            self.soil.advance(k * 1e-3, 1e-3, np.full(21, 1e4 * (1 + 0.1 * k)),
                              np.full(21, 1e4 * (1.1 + 0.1 * k)))
        self.assertTrue(np.all(np.isfinite(self.soil.u)))
        self.assertTrue(np.all(self.soil.u[strict] == 0.0))
        self.assertTrue(math.isfinite(self.soil.dt) and self.soil.dt > 0.0)


class Statics(unittest.TestCase):
    def test_the_static_state_with_a_trench_is_at_rest(self):
        # with the static far field and the footprints' compliance on: the
        # static state under a constant load stays at rest, exactly, and the
        # held nodes (the trench's inner ones, the symmetry plane's u_y) at
        # zero
        p, _ = block([TRENCH], static_reach=5.0, footprint_compliance=True)
        soil = FESoil(p)
        forces = np.full(21, 1e4)
        self.assertTrue(np.all(soil.statics(forces) > 0.0))
        held = soil.mask == 0.0
        for k in range(10):
            soil.advance(k * 1e-3, 1e-3, forces, forces)
        self.assertEqual(float(np.abs(soil.v).max()), 0.0)
        # held: zero to the static solver's round-off (the symmetry plane's
        # u_y comes out of it at about 1e-31 m, as without a trench)
        self.assertLessEqual(float(np.abs(soil.u[held]).max()), 1e-20 * np.abs(soil.u).max())


if __name__ == "__main__":
    unittest.main()
