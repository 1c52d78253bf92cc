"""The partitioned convolution (track.py: lags below L summed at each step,
the rest by FFT once per block of L steps) against the direct sum over the
whole memory (block = 1), on the ground-vibration scene's layers: six
footprints, a receiver, M = 200 memory steps (L = 28), 700 steps of random
forces with jumps at the steps' starts (the newest increment moved) and
save / step / restore in the middle of blocks, as implicit coupling does.
Displacements, velocities and receiver velocities agree to 1e-12 of their
largest value at every step (measured: 8e-15, 2e-16, 9e-16). The
receivers have a memory of their own (receiver_memory, here 0.6 s: 300
steps, L = 34): their velocities do not depend on the footprints'
memory, bit for bit."""
import tempfile
import unittest

import numpy as np

import support
from green_soil.track import TrackSoil

FPS = [(0.3 + 0.6 * k, 0.65, 0.6, 1.3) for k in range(6)]


class BlockedTest(unittest.TestCase):
    def test_partitioned_equals_direct(self):
        with tempfile.TemporaryDirectory(prefix="green_blocked_") as cache:
            soils = [TrackSoil(support.LAYERED, FPS, [(1.8, 8.0)], 2e-3, 0.4, f_max=80.0,
                               cache_dir=cache, workers=1, block=block, receiver_memory=0.6)
                     for block in (1, None)]
        direct, blocked = soils
        self.assertEqual((direct.M, direct.coupling.block, blocked.coupling.block), (200, 1, 28))
        self.assertEqual((direct.M_receivers, blocked.receivers.block), (300, 34))
        rng = np.random.default_rng(3)
        forces = 1e4 * rng.standard_normal((700, 6))
        for soil in soils:
            soil.reset(forces[0])
        outs = [[], []]
        for k in range(1, 700):
            start = forces[k - 1] + (5.0 * rng.standard_normal(6) if k % 7 == 0 else 0.0)
            if k % 50 == 0:  # a trial step thrown away, mid-block
                for soil in soils:
                    state = soil.save()
                    soil.step(start, forces[k] + 1.0)
                    soil.restore(state)
            for out, soil in zip(outs, soils):
                out.append(soil.step(start, forces[k]))
        for i, name in enumerate(("displacement", "velocity", "receiver velocity")):
            want = np.array([o[i] for o in outs[0]])
            got = np.array([o[i] for o in outs[1]])
            scale = np.max(np.abs(want))
            self.assertGreater(scale, 0.0)
            worst = np.max(np.abs(got - want), axis=1)
            step = int(np.argmax(worst))
            self.assertLess(worst[step], 1e-12 * scale, "%s differs by %.3g of its peak at step %d"
                            % (name, worst[step] / scale, step + 1))

    def test_receivers_do_not_depend_on_the_footprints_memory(self):
        with tempfile.TemporaryDirectory(prefix="green_blocked_") as cache:
            soils = [TrackSoil(support.LAYERED, FPS, [(1.8, 8.0), (1.8, 16.0)], 2e-3, memory,
                               f_max=80.0, cache_dir=cache, workers=1, receiver_memory=0.6)
                     for memory in (0.1, 0.6)]
        self.assertEqual([s.M for s in soils], [50, 300])
        self.assertTrue(np.array_equal(soils[0].R, soils[1].R))
        rng = np.random.default_rng(4)
        forces = 1e4 * rng.standard_normal((400, 6))
        outs = [[], []]
        for out, soil in zip(outs, soils):
            soil.reset(forces[0])
            for k in range(1, 400):
                out.append(soil.step(forces[k - 1], forces[k])[2])
        self.assertTrue(np.array_equal(np.array(outs[0]), np.array(outs[1])))
        # The footprints do: a memory of 0.1 s truncates their responses.
        self.assertFalse(np.array_equal(soils[0].S[0], soils[1].S[0]))


if __name__ == "__main__":
    unittest.main()
