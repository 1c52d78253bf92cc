#!/usr/bin/env python3
"""The wall time per macro step of a run whose soil is a physics-free
participant on the Python SDK, against the same participant on the C++
package, as the master runs them.

Serves, one after the other and alternating, the example soil with an
advance() that computes nothing (bench/python_sdk_overhead.py's NoPhysics)
and build/bin/cpp_sdk_overhead --serve (the C++ package's NodeSession with
a step that computes nothing), and times `master run --case ss-xx-jacobi
--judge none` on scenes/soil.toml with micro_steps = 10 (2,500 macro
steps) against each, on the direct and on the relay data plane. The time
is the run's own (summary.json's wall_s: the macro steps, not the start-up
or the judgement), divided by its macro steps. Prints each run and, per
plane, the best of each package and their ratio (Python over C++).

Usage: /usr/bin/python3 bench/sdk_wall.py [BUILD_BIN] [--repeats N]
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(here)

PY_SERVER = """
import runpy, sys
sys.path.insert(0, %r)
import railcosim_sdk as rc
SOIL = runpy.run_path(%r)
class NoPhysics(SOIL["LumpedSoil"]):
    def advance(self, t, H, inputs):
        return self.outputs()
sys.argv = [sys.argv[0]] + sys.argv[1:]
rc.serve(NoPhysics())
""" % (os.path.join(root, "sdk", "python"),
       os.path.join(root, "examples", "python_soil", "soil_participant.py"))


def start(cmd):
    """Starts a server and returns it with the address it prints."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for _ in range(50):
        line = p.stdout.readline()
        m = re.search(r"listening on (\S+)", line)
        if m:
            return p, m.group(1)
    p.kill()
    sys.exit("the server did not say where it listens: %s" % " ".join(cmd))


def run_once(master, scene, address, plane, out):
    cmd = [master, "run", "--scene", scene, "--case", "ss-xx-jacobi", "--judge", "none",
           "--node", "soil=" + address, "--data-plane", plane, "--out", out]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "ss-xx-jacobi", "summary.json")) as f:
        s = json.load(f)
    return s["wall_s"] / s["macro_steps"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bin", nargs="?", default=os.path.join(root, "build", "bin"))
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    master = os.path.join(args.bin, "master")
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "soil10.toml")
        text = open(os.path.join(root, "scenes", "soil.toml")).read()
        text = re.sub(r"^(tolerance = .*)$", r"\1\nmicro_steps = 10", text, count=1, flags=re.M)
        open(scene, "w").write(text)
        servers = {
            "C++": start([os.path.join(args.bin, "cpp_sdk_overhead"), "--serve"]),
            "Python": start(["/usr/bin/python3", "-c", PY_SERVER, "--config", scene]),
        }
        best = {}
        try:
            for plane in ("direct", "relay"):
                for k in range(args.repeats):
                    for name, (_, address) in servers.items():
                        t = run_once(master, scene, address, plane, os.path.join(tmp, "o"))
                        print("%-8s %-6s run %d: %.1f us per macro step" % (plane, name, k + 1,
                                                                          t * 1e6))
                        best[plane, name] = min(best.get((plane, name), 1e9), t)
        finally:
            for p, _ in servers.values():
                p.kill()
        for plane in ("direct", "relay"):
            c, p = best[plane, "C++"], best[plane, "Python"]
            print("%s: best C++ %.1f us, best Python %.1f us, Python / C++ %.2f"
                  % (plane, c * 1e6, p * 1e6, p / c))


if __name__ == "__main__":
    main()
