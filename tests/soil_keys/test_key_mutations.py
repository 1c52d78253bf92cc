"""The scene fuzzer for the soils the master starts: every number of the
[soil] tables of scenes/ground_vibration_ci.toml (FE soil) and
scenes/ground_vibration_green_ci.toml (Green's-function soil), layers
included, mutated to the values that broke loaders before (0, negative,
huge, subnormal, past int64, nan/inf, wrong types), goes through the check
the master runs before it starts the soil and under `master run --check`
(the SDK's --check-configure on a Configure with the footprints a track of
the CI scene has). Each mutant is either accepted, and then its block fits
the machine, or refused with exit status 2 and a message naming the
[soil] key, within a second, never a traceback or another exception.
Runs without dolfinx (the check imports none)."""
import contextlib
import io
import os
import re
import sys
import time
import unittest

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, SRC)
sys.path.insert(0, os.path.join(SRC, "sdk", "python"))

from railcosim_sdk.server import check_configure  # noqa: E402
from railcosim_sdk.wire import pb  # noqa: E402

MUTATIONS = ["0", "-1", "-0.5", "1e308", "5e-324", "4294967346", "-4294967296",
             "9223372036854775807", "nan", "inf", "-inf", "1e-30", "1e30", '"text"', "true",
             "[1.0]", "[]", "{}"]


def soil_tables(text):
    """The lines of the [soil] and [[soil.layers]] tables: (line index, key,
    value) for every key = number or key = [numbers]."""
    lines = text.split("\n")
    out, inside = [], False
    for k, line in enumerate(lines):
        header = re.match(r"^\s*\[\[?([\w.]+)\]\]?", line)
        if header:
            inside = header.group(1) in ("soil", "soil.layers")
            continue
        m = re.match(r"^(\s*(\w+)\s*=\s*)([-+0-9.eE]+|\[[^\]]*\])(.*)$", line)
        if inside and m:
            out.append((k, m.group(2), m))
    return lines, out


def soil_text(lines):
    """The [soil] table and its layers as TOML text (what Configure.own_config
    carries), from the scene's lines."""
    keep, inside = [], False
    for line in lines:
        header = re.match(r"^\s*\[\[?([\w.]+)\]\]?", line)
        if header:
            inside = header.group(1) in ("soil", "soil.layers")
            if inside:
                keep.append("[[layers]]" if header.group(1) == "soil.layers" else "")
            continue
        if inside:
            keep.append(line)
    return "\n".join(keep)


def configure(own_config):
    """The Configure a master sends the soil of the CI scenes: one ss
    interface, 50 sleepers 0.6 m apart, footprints 0.6 x 2.5 m (half a
    sleeper's bearing each side of the axis)."""
    c = pb.Configure()
    c.participant = "soil"
    c.macro_step = 1e-4
    c.end_time = 0.02
    c.own_config = own_config
    i = c.interfaces.add()
    i.cut, i.peer, i.upper = "ss", "track", False
    i.receives.append(pb.FORCE)
    i.sends.extend([pb.DISPLACEMENT, pb.VELOCITY])
    for k in range(50):
        i.x.append(0.6 * k)
        f = i.footprints.add()
        f.x, f.y, f.length, f.width = 0.6 * k, 0.75, 0.6, 0.5
    return c.SerializeToString()


def checked(participant, own_config):
    err = io.StringIO()
    start = time.monotonic()
    with contextlib.redirect_stderr(err):
        status = check_configure(participant, configure(own_config))
    return status, err.getvalue(), time.monotonic() - start


class Mutations(unittest.TestCase):
    def mutate_all(self, scene, participant):
        with open(os.path.join(SRC, "scenes", scene)) as f:
            lines, keys = soil_tables(f.read())
        status, err, _ = checked(participant, soil_text(lines))
        self.assertEqual(status, 0, "the scene itself: " + err)
        self.assertGreater(len(keys), 8)
        refused = 0
        for k, key, m in keys:
            for value in MUTATIONS:
                mutant = list(lines)
                mutant[k] = m.group(1) + value + m.group(4)
                with self.subTest(scene=scene, key=key, line=k + 1, value=value):
                    status, err, seconds = checked(participant, soil_text(mutant))
                    self.assertIn(status, (0, 2), err)
                    self.assertLess(seconds, 1.0)
                    if status == 2:
                        refused += 1
                        self.assertIn("[soil] ", err)
                        self.assertNotIn("Traceback", err)
                        named = key if key != "receivers" else "receivers"
                        self.assertTrue(named in err or "layers" in err, err)
        self.assertGreater(refused, len(keys) * 8)  # nan, inf, text, ... are refused everywhere
        return refused

    def test_fe_soil(self):
        from fe_soil.participant import FESoilParticipant
        self.mutate_all("ground_vibration_ci.toml", FESoilParticipant(None, None, None))

    def test_green_soil(self):
        from green_soil.participant import GreenSoilParticipant
        self.mutate_all("ground_vibration_green_ci.toml", GreenSoilParticipant())


if __name__ == "__main__":
    unittest.main()
