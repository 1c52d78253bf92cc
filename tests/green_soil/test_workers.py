"""The Green's functions computed by several worker processes, each taking
a block of the frequencies, are bit for bit those of one process: the
blocks share the wavenumber grid (that of the highest frequency of all),
the radial grid and the footprint quadrature. Checked for 2 and 3 workers
(3 does not divide the frequencies evenly, so the blocks differ in size),
footprint pairs on both rails and receiver points, on the ground-vibration
scene's layers with their damping; and the cache key does not depend on
the number of workers (a cache filled by one serves the other). Workers
end with the process that started them: a soil killed mid-build leaves
none computing."""
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

import support
from green_soil import config, responses as R

FP = R.Footprint(0.6, 1.3)
PAIRS = [(0.6 * k, 0.0) for k in range(8)] + [(0.6 * k, 1.3) for k in range(8)]
POINTS = [(0.0, 7.35), (0.0, 8.65), (0.0, 15.35)]
REC = R.Record(dt=2e-3, duration=0.5, f_max=60.0)


class WorkerCountTest(unittest.TestCase):
    """[soil] workers = 256 on two cores once started 154 processes: a pool
    is held to WORKERS_PER_CORE processes per usable core, and says so."""

    def test_a_pool_is_held_to_its_cores(self):
        import contextlib
        import io
        cores = R.usable_cores()
        self.assertEqual(R.worker_count(0), cores)
        self.assertEqual(R.worker_count(1), 1)
        note = io.StringIO()
        with contextlib.redirect_stderr(note):
            self.assertEqual(R.worker_count(256), R.WORKERS_PER_CORE * cores)
        self.assertIn("[soil] workers = 256 held to %d" % (R.WORKERS_PER_CORE * cores), note.getvalue())


class WorkersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        _, cls.w = REC.frequencies()
        cls.serial = R.spectra(support.LAYERED, FP, PAIRS, POINTS, cls.w, workers=1)

    def test_blocks_are_bitwise_the_serial_result(self):
        self.assertEqual(len(self.w), 61)  # split 31 + 30 and 21 + 20 + 20
        for workers in (2, 3):
            pairs, points = R.spectra(support.LAYERED, FP, PAIRS, POINTS, self.w, workers=workers)
            for name, got, want in (("pairs", pairs, self.serial[0]),
                                    ("points", points, self.serial[1])):
                self.assertEqual(got.shape, want.shape)
                diff = np.max(np.abs(got - want)) / np.max(np.abs(want))
                self.assertTrue(np.array_equal(got, want),
                                "%s with %d workers differ from one worker by %.3g relative"
                                % (name, workers, diff))

    def test_workers_key(self):
        layers = [{"thickness": 1.0, "density": 1800.0, "shear_wave_speed": 200.0,
                   "poisson": 0.25}]
        self.assertEqual(config.parse({"layers": layers})["workers"], 0)
        self.assertEqual(config.parse({"layers": layers, "workers": 2})["workers"], 2)
        for bad in (-1, 1.5, True, 257):
            with self.assertRaisesRegex(config.ConfigError, r"\[soil\] workers must be an integer"):
                config.parse({"layers": layers, "workers": bad})

    def test_usable_cores_is_the_affinity(self):
        self.assertEqual(R.usable_cores(), len(os.sched_getaffinity(0)))

    def test_cache_is_shared_between_worker_counts(self):
        with tempfile.TemporaryDirectory(prefix="green_workers_") as cache:
            p2, q2, hit2 = R.cached_spectra(support.LAYERED, FP, PAIRS, POINTS, REC,
                                            cache_dir=cache, workers=2)
            p1, q1, hit1 = R.cached_spectra(support.LAYERED, FP, PAIRS, POINTS, REC,
                                            cache_dir=cache, workers=1)
            self.assertEqual((hit2, hit1), (False, True))
            self.assertTrue(np.array_equal(p1, self.serial[0]))
            self.assertTrue(np.array_equal(q1, self.serial[1]))
            self.assertTrue(np.array_equal(p2, p1))



def children(pid):
    """The live (not zombie) processes whose parent is pid."""
    out = []
    for name in os.listdir("/proc"):
        try:
            with open("/proc/%s/stat" % name) as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[1]) == pid and fields[0] != "Z":
            out.append(int(name))
    return out


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


# A build of minutes in two workers (footprint pairs to 120 m, 0 to 100 Hz).
LONG_BUILD = """
import sys
sys.path.insert(0, sys.argv[1])
import support
from green_soil import responses as R
rec = R.Record(dt=1e-3, duration=4.0, f_max=100.0)
pairs = [(0.6 * k, 0.0) for k in range(200)]
R.spectra(support.LAYERED, R.Footprint(0.6, 1.3), pairs, [], rec.frequencies()[1], workers=2)
"""


class WorkersEndWithTheirParent(unittest.TestCase):
    def test_killed_mid_build(self):
        here = os.path.dirname(os.path.abspath(__file__))
        p = subprocess.Popen([sys.executable, "-c", LONG_BUILD, here], cwd=here)
        workers = []
        try:
            deadline = time.monotonic() + 60.0
            while len(workers) < 2 and time.monotonic() < deadline and p.poll() is None:
                time.sleep(0.1)
                workers = children(p.pid)
            self.assertEqual(len(workers), 2, "the build did not start two workers")
            time.sleep(1.0)  # at work on their blocks
            p.send_signal(signal.SIGKILL)
            p.wait(timeout=10)
            deadline = time.monotonic() + 10.0
            while any(alive(w) for w in workers) and time.monotonic() < deadline:
                time.sleep(0.1)
            left = [w for w in workers if alive(w)]
            self.assertEqual(left, [], "workers still computing 10 s after their parent was killed")
        finally:
            for w in workers:
                if alive(w):
                    os.kill(w, signal.SIGKILL)
            if p.poll() is None:
                p.kill()


if __name__ == "__main__":
    unittest.main()
