#!/usr/bin/env python3
"""The Python SDK's compiled-schema cache runs no code another local user
could have put there. With the user's cache unusable (HOME and
XDG_CACHE_HOME under a regular file, as for a service account), the SDK
falls back to TMPDIR/railcosim-EUID; a railcosim_pb2.py planted there (in
the folder named by the schema's hash) that would write a marker file is
never run when the folder or the file belongs to another user (uid 65534,
set by chown when this test runs as root), can be written by others, or
is a symbolic link: the SDK warns naming the folder and still works (the
schema compiled into a fresh private folder). Unplanted, the fallback is
created 0700 and used again. Usage: python_sdk_cache_test.py SOURCE_DIR"""

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

SRC = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..")
PROTO = os.path.join(SRC, "protocol", "railcosim.proto")
OTHER = 65534  # nobody
with open(PROTO, "rb") as f:
    KEY = hashlib.sha256(f.read()).hexdigest()[:16]

IMPORT = ("import sys; sys.path.insert(0, %r); import railcosim_sdk as rc; "
          "print(rc.wire.pb.Envelope.DESCRIPTOR.full_name)" % os.path.join(SRC, "sdk", "python"))


class SchemaCache(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp()
        os.chmod(self.work, 0o755)
        self.tmp = os.path.join(self.work, "tmp")
        os.mkdir(self.tmp, 0o1777)
        os.chmod(self.tmp, 0o1777)  # a shared /tmp
        blocker = os.path.join(self.work, "not-a-folder")
        open(blocker, "w").close()
        self.marker = os.path.join(self.work, "marker")
        self.fallback = os.path.join(self.tmp, "railcosim-%d" % os.geteuid())
        self.env = {k: v for k, v in os.environ.items()
                    if k not in ("RAILCOSIM_SDK_CACHE", "RAILCOSIM_PROTO")}
        self.env.update(HOME=blocker, XDG_CACHE_HOME=os.path.join(blocker, "cache"),
                        TMPDIR=self.tmp, PYTHONDONTWRITEBYTECODE="1")

    def tearDown(self):
        shutil.rmtree(self.work, ignore_errors=True)

    def plant(self, root_mode=0o755, file_mode=0o644, owner=None, link=False):
        """The attacker's module at TMPDIR/railcosim-EUID/KEY/railcosim_pb2.py."""
        os.mkdir(self.fallback)
        os.chmod(self.fallback, root_mode)
        where = os.path.join(self.work, "elsewhere") if link else os.path.join(self.fallback, KEY)
        os.mkdir(where)
        if link:
            os.symlink(where, os.path.join(self.fallback, KEY))
        module = os.path.join(where, "railcosim_pb2.py")
        with open(module, "w") as f:
            f.write("open(%r, 'w').write('ran')\n" % self.marker)
        os.chmod(module, file_mode)
        if owner is not None:
            for path in owner:
                os.lchown(path if path != "file" else module, OTHER, OTHER)
        return module

    def run_sdk(self):
        p = subprocess.run(["/usr/bin/python3", "-c", IMPORT], capture_output=True, text=True,
                           timeout=60, env=self.env, cwd=self.work)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout.strip(), "railcosim.wire.Envelope")
        self.assertFalse(os.path.exists(self.marker), "the planted module ran: " + p.stderr)
        left = [n for n in os.listdir(self.tmp) if n.startswith("railcosim-schema-")]
        self.assertEqual(left, [], "temporary folders left behind")
        return p.stderr

    def need_root(self):
        if os.geteuid() != 0:
            self.skipTest("chown to another user needs root")

    def test_folder_of_another_user(self):
        self.need_root()
        self.plant(owner=[self.fallback])
        err = self.run_sdk()
        self.assertIn("%s belongs to uid %d" % (self.fallback, OTHER), err)

    def test_module_of_another_user(self):
        self.need_root()
        self.plant(owner=["file"])
        err = self.run_sdk()
        self.assertIn("belongs to uid %d" % OTHER, err)

    def test_world_writable_folder(self):
        self.plant(root_mode=0o777)
        self.assertIn("%s can be written by others (mode 777)" % self.fallback, self.run_sdk())

    def test_world_writable_module(self):
        self.plant(file_mode=0o666)
        self.assertIn("can be written by others (mode 666)", self.run_sdk())

    def test_linked_folder(self):
        self.plant(link=True)
        self.assertIn("%s is a symbolic link" % os.path.join(self.fallback, KEY), self.run_sdk())

    def test_group_writable_umask(self):
        # Under umask 002 the compiled module is still the owner's alone.
        p = subprocess.run(["/bin/sh", "-c", "umask 002 && exec /usr/bin/python3 -c \"$0\"",
                            IMPORT], capture_output=True, text=True, timeout=60, env=self.env)
        self.assertEqual((p.returncode, p.stderr), (0, ""))
        module = os.path.join(self.fallback, KEY, "railcosim_pb2.py")
        self.assertEqual(os.stat(module).st_mode & 0o022, 0)
        self.assertEqual(self.run_sdk(), "")

    def test_private_fallback_is_created_and_used(self):
        self.assertEqual(self.run_sdk(), "")
        self.assertEqual(os.stat(self.fallback).st_mode & 0o777, 0o700)
        module = os.path.join(self.fallback, KEY, "railcosim_pb2.py")
        self.assertTrue(os.path.isfile(module))
        before = os.stat(module).st_mtime_ns
        self.assertEqual(self.run_sdk(), "")
        self.assertEqual(os.stat(module).st_mtime_ns, before)  # read again, not compiled again
        # No temporary folder left behind in TMPDIR besides the cache.
        self.assertEqual(os.listdir(self.tmp), [os.path.basename(self.fallback)])


if __name__ == "__main__":
    unittest.main()
