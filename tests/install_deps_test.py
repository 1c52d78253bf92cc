#!/usr/bin/env python3
"""scripts/install-deps.sh by profile (`--list` prints a profile's packages
and installs nothing): the base, which scripts/run-main.sh installs for the
paper study, holds neither the FE soil's stack nor the test suite's tools;
--fe adds FEniCSx (python3-dolfinx), --green scipy, --tests clang,
clang-tidy, GoogleTest and GoogleMock; --all is every profile, what
scripts/run-tests.sh installs; an unknown option is refused naming it; and
no other script of the repository installs Debian packages (the list is in
one place). Usage: install_deps_test.py SOURCE_DIR"""

import glob
import os
import subprocess
import sys
import unittest

SRC = os.path.abspath(sys.argv.pop(1))
SCRIPT = os.path.join(SRC, "scripts", "install-deps.sh")


def listed(*profiles):
    out = subprocess.run(["bash", SCRIPT, *profiles, "--list"], capture_output=True, text=True,
                         timeout=30, check=True)
    return out.stdout.split()


class Profiles(unittest.TestCase):
    def test_base_is_what_the_paper_study_needs(self):
        base = listed()
        for p in ("cmake", "g++", "libprotobuf-dev", "protobuf-compiler", "libcli11-dev",
                  "python3-matplotlib", "python3-numpy", "libzip-dev", "libpugixml-dev"):
            self.assertIn(p, base)
        for p in ("python3-dolfinx", "python3-scipy", "clang", "clang-tidy", "libgtest-dev",
                  "libgmock-dev", "libclang-rt-14-dev"):
            self.assertNotIn(p, base)
        self.assertEqual(len(base), len(set(base)))

    def test_each_profile_adds_its_own(self):
        base = listed()
        self.assertEqual(listed("--fe"), base + ["python3-dolfinx"])
        self.assertEqual(listed("--green"), base + ["python3-scipy"])
        tests = listed("--tests")
        self.assertEqual(tests[:len(base)], base)
        for p in ("clang", "clang-tidy", "libgtest-dev", "libgmock-dev", "parallel", "iproute2"):
            self.assertIn(p, tests[len(base):])
        everything = listed("--all")
        self.assertEqual(sorted(everything), sorted(set(listed("--fe", "--green", "--tests"))))
        self.assertEqual(len(everything), len(set(everything)))

    def test_unknown_option_is_refused(self):
        out = subprocess.run(["bash", SCRIPT, "--bogus"], capture_output=True, text=True, timeout=30)
        self.assertEqual(out.returncode, 2)
        self.assertIn("unknown option --bogus", out.stderr)

    def test_the_scripts_install_by_profile(self):
        main = open(os.path.join(SRC, "scripts", "run-main.sh")).read()
        self.assertIn("scripts/install-deps.sh --fe", main)
        self.assertIn("scripts/install-deps.sh --green", main)
        run_tests = open(os.path.join(SRC, "scripts", "run-tests.sh")).read()
        self.assertIn("scripts/install-deps.sh --all", run_tests)
        for path in glob.glob(os.path.join(SRC, "scripts", "*")) + [os.path.join(SRC, "Dockerfile")]:
            if os.path.basename(path) != "install-deps.sh" and os.path.isfile(path):
                self.assertNotIn("apt-get install", open(path, errors="replace").read(), path)


if __name__ == "__main__":
    unittest.main()
