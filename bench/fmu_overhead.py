#!/usr/bin/env python3
"""What serving a participant as an FMU costs beside the same physics built
in, in one invocation (docs/benchmarks.md, "An FMU as a participant"): the
paper scene's vehicle (scenes/paper.toml, wr-xx-jacobi, 2,500 macro steps)
as the built-in vehicle and as its exported FMU (build/bin/fmus/
railcosim_vehicle.fmu, mapped in the scene by [vehicle.fmu]), whose runs
are equal bit for bit, so the difference is the FMU host's alone:

  inproc          both in the master's process
  tcp, direct     vehicle_node against an fmu_node the master starts
  tcp, relay      the same through the master's relay

Each pair alternates, REPEATS times, --judge none; the run's own wall_s
(summary.json) is taken, its median per variant, and the FMU's extra
microseconds per macro step over the built-in one's. The baseline is the
built-in run measured in the same invocation, which holds no FMU.

Usage: fmu_overhead.py BIN_DIR SOURCE_DIR [--repeats N]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

MAPPING = """
[vehicle.fmu]
file = "{fmu}"
wr_in_displacement = "wr_in_displacement"
wr_out_displacement = "wr_out_displacement"
history_wheel_m = "wheel_m"
history_contact_force_N = "contact_force_N"
"""


def run(master, scene, transport, plane, out):
    cmd = [master, "run", "--scene", scene, "--case", "wr-xx-jacobi", "--judge", "none",
           "--transport", transport, "--out", out]
    if plane:
        cmd += ["--data-plane", plane]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "wr-xx-jacobi", "summary.json")) as f:
        s = json.load(f)
    return s["wall_s"], s["macro_steps"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("bin_dir")
    p.add_argument("source_dir")
    p.add_argument("--repeats", type=int, default=7)
    a = p.parse_args()
    master = os.path.join(a.bin_dir, "master")
    fmu = os.path.abspath(os.path.join(a.bin_dir, "fmus", "railcosim_vehicle.fmu"))
    work = tempfile.mkdtemp(prefix="fmu_overhead_")
    builtin = os.path.join(a.source_dir, "scenes", "paper.toml")
    with open(builtin) as f:
        text = f.read()
    mapped = os.path.join(work, "vehicle_fmu.toml")
    with open(mapped, "w") as f:
        f.write(text + MAPPING.format(fmu=fmu))
    print("| transport | built-in vehicle, median wall | vehicle FMU, median wall | FMU / built-in "
          "| FMU's extra µs per macro step |")
    print("|---|---|---|---|---|")
    for transport, plane in (("inproc", None), ("tcp", "direct"), ("tcp", "relay")):
        walls = {"builtin": [], "fmu": []}
        steps = 0
        for k in range(a.repeats):
            for name, scene in (("builtin", builtin), ("fmu", mapped)):
                wall, steps = run(master, scene, transport, plane,
                                  os.path.join(work, "%s-%s-%d" % (name, plane or transport, k)))
                walls[name].append(wall)
        b, f = statistics.median(walls["builtin"]), statistics.median(walls["fmu"])
        print("| %s | %.4f s | %.4f s | %.3f | %.1f |"
              % (transport + (", " + plane if plane else ""), b, f, f / b, 1e6 * (f - b) / steps))
        sys.stdout.flush()


main()
