#!/usr/bin/env python3
"""What a single `master run` with a participant given by address costs to
judge, beside the run itself, in one invocation (docs/benchmarks.md, "The
verdict's cost"): the example Python soil (examples/python_soil) on
scenes/soil.toml, one case, run three times from a fresh node each:

  --judge none       the run alone (the baseline: nothing judged)
  --judge stability  the run and its stability measure (matrix-free)
  --judge full       the default: stability and the co-simulation reference

Each is timed around the whole command; the ratios are over the baseline
measured in the same invocation, which holds no judgement.

Usage: node_judge_cost.py BIN_DIR SOURCE_DIR [--case CASE] [--end-time S]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time


def start_soil(src, scene, env):
    out = tempfile.NamedTemporaryFile("w+", suffix=".out", delete=False)
    proc = subprocess.Popen(["/usr/bin/python3", os.path.join(src, "examples", "python_soil",
                                                              "soil_participant.py"),
                             "--config", scene], stdout=out, stderr=subprocess.DEVNULL, env=env)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        with open(out.name) as f:
            m = re.search(r"^listening on (\S+)$", f.read(), re.M)
        if m:
            return proc, m.group(1)
        time.sleep(0.1)
    proc.kill()
    sys.exit("the Python soil did not start within 30 s")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bin_dir")
    ap.add_argument("source_dir")
    ap.add_argument("--case", default="ss-xt-jacobi")
    ap.add_argument("--end-time", type=float, default=0.05, help="s (default 0.05)")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="node_judge_cost_")
    with open(os.path.join(a.source_dir, "scenes", "soil.toml")) as f:
        text = re.sub(r"(?m)^end_time = .*$", "end_time = %r" % a.end_time, f.read())
    # The example soil integrates with fixed micro steps, 10 a macro step
    # (as tests/study_any_test.py runs it); the soil's own window is left out.
    text = re.sub(r"(?m)^ss_macro_step = .*$", "", text)
    text = re.sub(r"(?m)^(tolerance = .*)$", r"\1\nmicro_steps = 10", text)
    scene = os.path.join(work, "soil.toml")
    with open(scene, "w") as f:
        f.write(text)
    env = dict(os.environ, RAILCOSIM_SDK_CACHE=os.path.join(work, "cache"))
    rows = []
    for judge in ("none", "stability", "full"):
        proc, address = start_soil(a.source_dir, scene, env)
        try:
            t0 = time.monotonic()
            p = subprocess.run([os.path.join(a.bin_dir, "master"), "run", "--scene", scene,
                                "--case", a.case, "--node", "soil=" + address, "--judge", judge,
                                "--out", os.path.join(work, judge)],
                               capture_output=True, text=True, env=env)
            wall = time.monotonic() - t0
        finally:
            proc.kill()
            proc.wait()
        if p.returncode not in (0, 2):
            sys.exit("%s: exit %d\n%s" % (judge, p.returncode, p.stderr[-2000:]))
        with open(os.path.join(work, judge, a.case, "summary.json")) as f:
            s = json.load(f)
        rows.append((judge, wall, s["wall_s"], s["status"]))
    base = rows[0][1]
    print("node_judge_cost: %s on scenes/soil.toml to %g s with the example Python soil"
          % (a.case, a.end_time))
    print("| --judge | command wall (s) | run wall_s (s) | status | / --judge none |")
    print("|---|---|---|---|---|")
    for judge, wall, run_s, status in rows:
        print("| %s | %.2f | %.2f | %s | %.1f |" % (judge, wall, run_s, status, wall / base))


if __name__ == "__main__":
    main()
