"""The Green's functions' cache (green_soil/cache.py) in a folder others
can write, or one that cannot be written: an entry with its spectra x 10
(its digest kept, or recomputed by another user),
of another shape, with a NaN, a FIFO, a link, a deflated member that
would inflate to 200 MB, or links planted at temporary names are never
used nor followed: each is warned about, computed again and rewritten;
a folder that cannot be written or a disk that fills costs only the
cache (one warning, the right result, no temporary file left)."""
import contextlib
import errno
import io
import os
import shutil
import tempfile
import time
import unittest
import zipfile

import numpy as np

import support
from green_soil import cache, responses as R

FP = R.Footprint(0.6, 1.3)
PAIRS = [(0.0, 0.0), (0.6, 0.0), (0.0, 1.3)]
POINTS = [(0.0, 8.0), (0.6, 8.0)]
REC = R.Record(dt=4e-3, duration=0.5, f_max=30.0)
LAYERS = support.HALF_SPACE


def spectra(cache_dir):
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        pairs, points, hit = R.cached_spectra(LAYERS, FP, PAIRS, POINTS, REC, cache_dir=cache_dir)
    return pairs, points, hit, err.getvalue()


class CacheTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        _, w = REC.frequencies()
        cls.want = R.spectra(LAYERS, FP, PAIRS, POINTS, w)
        cls.key = R.cache_key(LAYERS, FP, PAIRS, POINTS, REC, R.greens.Discretisation())

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="green_cache_")
        self.path = os.path.join(self.dir, self.key + ".npz")
        cache._warned.clear()

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def assert_right(self, pairs, points):
        self.assertTrue(np.array_equal(pairs, self.want[0]))
        self.assertTrue(np.array_equal(points, self.want[1]))

    def assert_recomputed(self, *words):
        """The planted entry is refused (warned), the result computed again
        and the entry rewritten: the next call is a hit."""
        pairs, points, hit, err = spectra(self.dir)
        self.assertFalse(hit)
        self.assert_right(pairs, points)
        for w in words:
            self.assertIn(w, err)
        self.assertIn("computed again", err)
        pairs, points, hit, err = spectra(self.dir)
        self.assertTrue(hit, err)
        self.assert_right(pairs, points)
        self.assertEqual(sorted(os.listdir(self.dir)), [self.key + ".npz"])

    def test_filled_then_hit(self):
        *_, hit, err = spectra(self.dir)
        self.assertEqual((hit, err), (False, ""))
        pairs, points, hit, err = spectra(self.dir)
        self.assertEqual((hit, err), (True, ""))
        self.assert_right(pairs, points)
        self.assertEqual(os.listdir(self.dir), [self.key + ".npz"])  # no temporary left

    def test_scaled_entry(self):
        spectra(self.dir)
        with np.load(self.path) as z:
            entry = {k: z[k] for k in z.files}
        entry["pairs"] = entry["pairs"] * 10.0  # the digest kept as it was
        np.savez(self.path, **entry)
        self.assert_recomputed("do not match their checksum")

    def test_entry_of_another_key(self):
        other = [("pairs", self.want[0] * 10.0), ("points", self.want[1])]
        cache.store(self.dir, self.path, "another key", other)
        self.assert_recomputed("checksum")

    def test_wrong_shape_and_nan(self):
        cache.store(self.dir, self.path, self.key, [("pairs", self.want[0][:2]),
                                                   ("points", self.want[1])])
        self.assert_recomputed("its pairs is complex128 (2, %d)" % self.want[0].shape[1])
        bad = self.want[1].copy()
        bad[0, 3] = np.nan
        cache.store(self.dir, self.path, self.key, [("pairs", self.want[0]), ("points", bad)])
        self.assert_recomputed("not finite in points")

    def test_entry_of_another_user_or_writable_by_others(self):
        # A forger who can write the folder recomputes the digest: only this
        # user's own entries are used.
        forged = [("pairs", self.want[0] * 10.0), ("points", self.want[1])]
        cache.store(self.dir, self.path, self.key, forged)
        os.chmod(self.path, 0o666)
        self.assert_recomputed("others may write it (mode 666)")
        if os.geteuid() == 0:
            cache.store(self.dir, self.path, self.key, forged)
            os.chown(self.path, 65534, 65534)
            self.assert_recomputed("it belongs to uid 65534")

    def test_fifo_entry(self):
        os.mkfifo(self.path)
        start = time.monotonic()
        self.assert_recomputed("not a regular file")
        self.assertLess(time.monotonic() - start, 60.0)

    def test_link_entry_and_links_at_temporary_names(self):
        victim = os.path.join(self.dir, "victim")
        with open(victim, "w") as f:
            f.write("the victim's file")
        os.symlink(victim, self.path)
        for pid in range(os.getpid() - 2, os.getpid() + 3):  # the old code's temporary names
            os.symlink(victim, self.path + ".%d.tmp.npz" % pid)
        pairs, points, hit, err = spectra(self.dir)
        self.assertFalse(hit)
        self.assert_right(pairs, points)
        self.assertIn("cannot be read", err)
        with open(victim) as f:
            self.assertEqual(f.read(), "the victim's file")
        self.assertFalse(os.path.islink(self.path))  # the link replaced, not followed
        self.assertTrue(spectra(self.dir)[2])

    def test_deflated_member(self):
        n_w = self.want[0].shape[1]
        with zipfile.ZipFile(self.path, "w", zipfile.ZIP_DEFLATED) as z:
            header = io.BytesIO()
            np.lib.format.write_array_header_1_0(header, {"descr": "<c16", "fortran_order": False,
                                                          "shape": (len(PAIRS), n_w)})
            with z.open("pairs.npy", "w", force_zip64=True) as m:
                m.write(header.getvalue())
                block = bytes(1 << 20)
                for _ in range(200):
                    m.write(block)
            z.writestr("points.npy", b"")
            z.writestr("digest.npy", b"")
        self.assertLess(os.path.getsize(self.path), 1 << 20)
        self.assert_recomputed("its pairs holds %d bytes" % (200 * (1 << 20) + len(
            header.getvalue())))

    def test_folder_cannot_be_made_or_written(self):
        blocker = os.path.join(self.dir, "file")
        open(blocker, "w").close()
        for where in (os.path.join(blocker, "green"), "/proc/self"):
            cache._warned.clear()
            with self.subTest(cache_dir=where):
                pairs, points, hit, err = spectra(where)
                self.assertFalse(hit)
                self.assert_right(pairs, points)
                self.assertIn("computed without caching, which costs only time", err)
                self.assertEqual(spectra(where)[3], "")  # warned once

    def test_full_disk_leaves_no_temporary(self):
        real = np.savez

        def full(f, **arrays):
            f.write(b"PK\x03\x04" + bytes(1000))
            raise OSError(errno.ENOSPC, "No space left on device")

        cache.np.savez = full
        try:
            pairs, points, hit, err = spectra(self.dir)
        finally:
            cache.np.savez = real
        self.assert_right(pairs, points)
        self.assertIn("No space left on device", err)
        self.assertEqual(os.listdir(self.dir), [])


if __name__ == "__main__":
    unittest.main()
