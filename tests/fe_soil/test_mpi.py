"""The soil on two MPI ranks gives what it gives on one: statics (with the
static far field), footprint outputs and receiver velocities after a pulse
(to 1e-7 relative; only the order of parallel sums differs)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

from support import HALF_SPACE, Footprint, SoilParams, ricker, uniform_nodes

from mpi4py import MPI


def run_case():
    from fe_soil.model import FESoil

    p = SoilParams(
        length=16.0, half_width=10.0, depth=8.0, layers=[HALF_SPACE],
        footprints=[Footprint(8.0, 1.0, 1.0), Footprint(8.6, 0.25, 2.6)],
        receivers=[(8.0, 4.0), (8.0, 8.0)], static_reach=5.0,
        x_nodes=uniform_nodes(0, 16, 0.5), y_nodes=uniform_nodes(0, 10, 0.5), z_nodes=uniform_nodes(-8, 0, 0.5))
    soil = FESoil(p)
    w0 = soil.statics([1e4, 2e4])
    H = 2e-3
    for k in range(60):
        load = [[1e4 + 1e5 * ricker(t, 15.0, 0.08), 2e4] for t in (k * H, (k + 1) * H)]
        w, v = soil.advance(k * H, H, *load)
    _, vr = soil.receiver_series()
    return {"statics": w0.tolist(), "w": w.tolist(), "v": v.tolist(), "receivers": vr[:, :, 2].tolist()}


class TwoRanks(unittest.TestCase):
    def test_two_ranks_agree_with_one(self):
        mpirun = shutil.which("mpirun")
        self.assertIsNotNone(mpirun, "mpirun is missing (python3-dolfinx brings MPI)")
        one = run_case()
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "two.json")
            env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                       OMPI_MCA_rmaps_base_oversubscribe="1")
            proc = subprocess.run([mpirun, "-n", "2", sys.executable, __file__, "--write", out],
                                  env=env, capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr[-2000:])
            with open(out) as f:
                two = json.load(f)
        for key in one:
            a, b = np.array(one[key]), np.array(two[key])
            self.assertEqual(a.shape, b.shape, key)
            np.testing.assert_allclose(b, a, rtol=1e-7, atol=1e-7 * np.max(np.abs(a)), err_msg=key)
        self.assertGreater(np.max(np.abs(one["receivers"])), 0.0)


if __name__ == "__main__":
    if "--write" in sys.argv:
        result = run_case()
        if MPI.COMM_WORLD.rank == 0:
            with open(sys.argv[sys.argv.index("--write") + 1], "w") as f:
                json.dump(result, f)
    else:
        unittest.main()
