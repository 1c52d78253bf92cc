#!/usr/bin/python3
"""The FE soil at its own window (multirate) against the single-rate run,
on a ground-vibration scene: what the soil costs and what the answer moves.

Usage:  bench/fe_soil_windows.py --master build/bin/master --out DIR
            [--scene scenes/ground_vibration.toml] [--case ss-xt-jacobi]
            [--windows 5,10,2] [--nearest 4] [--farthest 16] [--repeats 1]

It runs `master run` once at one rate (the ss cut at the macro step H,
`--macro-step ss=H`: the baseline, measured in this same invocation), then
once per window M H (`--macro-step ss=M*H`), one run at a time, with
the scene's settings otherwise. Per run: the run's wall time
(summary.json), the FE soil's own time (the clock it prints at the end of a
run on stderr: its static solves and its macro steps), its share of the
run (its macro steps' time over the run's wall time), and the baseline's
soil stepping time and share over the run's. Against the
baseline, over the receivers from --nearest to --farthest m and every
vertical one-third-octave band both runs hold (vibration.csv): the largest
difference of PPV (20 log10 of the ratio) and of the band levels, in dB,
over every band and over the bands up to --band-max Hz (those the mesh
resolves).
Run it niced (`nice -n 10`) on a shared machine: the times are wall times;
with --repeats the runs of every window interleave and each time is the
fastest of its repeats (each run's row goes to stderr as it ends).
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import time

# fe_soil/participant.py's report_time(): "... %d static solves %.1f s; %d macro steps %.1f s"
SOIL_CLOCK = re.compile(r"fe_soil: .*?built in ([0-9.]+) s; (\d+) static solves ([0-9.]+) s; "
                        r"(\d+) macro steps ([0-9.]+) s")


def run(master, scene, case, out, window):
    """One master run; its numbers (dict)."""
    os.makedirs(out, exist_ok=True)
    cmd = [master, "run", "--scene", scene, "--case", case, "--out", out,
           "--macro-step", "ss=%r" % window]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    with open(os.path.join(out, "master.log"), "w") as f:
        f.write(p.stdout + p.stderr)
    if p.returncode != 0:
        sys.exit("%s failed (exit %d); its output is in %s/master.log"
                 % (" ".join(cmd), p.returncode, out))
    clock = SOIL_CLOCK.search(p.stderr)
    if clock is None:
        sys.exit("%s: the FE soil's clock line (fe_soil: ... macro steps ... s) is not in its "
                 "output (%s/master.log)" % (" ".join(cmd), out))
    folder = os.path.join(out, case)
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    if summary.get("status") != "ok":
        sys.exit("%s ended with status %r (%s)" % (" ".join(cmd), summary.get("status"), folder))
    return {"window": window, "wall": wall, "run_wall": float(summary["wall_s"]),
            "build": float(clock.group(1)), "statics": float(clock.group(3)),
            "steps": int(clock.group(4)), "stepping": float(clock.group(5)),
            "share": float(clock.group(5)) / wall, "vibration": read_vibration(os.path.join(folder, "vibration.csv"))}


def read_vibration(path):
    with open(path, newline="") as f:
        return {float(r["y_m"]): r for r in csv.DictReader(f)}


def db(a, b):
    """20 log10(a / b); 0 for two equal values, inf where one is not finite or zero."""
    if a == b:
        return 0.0
    if not (math.isfinite(a) and math.isfinite(b)) or a <= 0.0 or b <= 0.0:
        return math.inf
    return 20.0 * math.log10(a / b)


def band_centre(column):
    """Lv_z_12.5893Hz_dB -> 12.5893."""
    return float(column[len("Lv_z_"):-len("Hz_dB")])


def largest_differences(base, other, nearest, farthest, band_max=math.inf):
    """(largest |dB| of PPV, where), (largest |dB| of a band level up to
    band_max Hz, where)."""
    ppv, band = (0.0, ""), (0.0, "")
    for y, r in base.items():
        if not nearest - 1e-9 <= y <= farthest + 1e-9:
            continue
        o = other[y]
        d = abs(db(float(o["ppv_mps"]), float(r["ppv_mps"])))
        if d >= ppv[0]:
            ppv = (d, "%g m" % y)
        for c in r:
            if not c.startswith("Lv_z_") or band_centre(c) > band_max * (1 + 1e-9):
                continue
            a, b = float(r[c]), float(o[c])
            if not math.isfinite(a) and not math.isfinite(b):
                continue  # a band neither record holds
            d = abs(b - a) if math.isfinite(a) and math.isfinite(b) else math.inf
            if d >= band[0]:
                band = (d, "%g m, %s" % (y, c))
    return ppv, band


def row(r, base, args):
    ppv, band = largest_differences(base["vibration"], r["vibration"], args.nearest, args.farthest)
    low = largest_differences(base["vibration"], r["vibration"], args.nearest, args.farthest,
                              args.band_max)[1]
    return ("%9.3g %6d %8.1f %8.1f %9.1f %6.3f %7.2f %7.2f %6.3f %-6s %6.3f %-28s %6.3f %s" % (
        r["window"], r["steps"], r["wall"], r["statics"], r["stepping"], r["share"],
        base["stepping"] / r["stepping"], base["share"] / r["share"], ppv[0], ppv[1], band[0],
        band[1], low[0], low[1]))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--master", required=True, help="build/bin/master")
    ap.add_argument("--out", required=True, help="a folder for the runs (one per window)")
    ap.add_argument("--scene", default=os.path.join(here, "..", "scenes", "ground_vibration.toml"))
    ap.add_argument("--case", default="ss-xt-jacobi")
    ap.add_argument("--windows", default="5,10,2", help="the soil's windows, in macro steps H")
    ap.add_argument("--nearest", type=float, default=4.0, help="m: the nearest receiver compared")
    ap.add_argument("--farthest", type=float, default=16.0, help="m: the farthest one")
    ap.add_argument("--band-max", type=float, default=20.0, help="Hz: the last column's "
                    "bands end here (the scene's resolved frequency; default 20)")
    ap.add_argument("--repeats", type=int, default=1, help="runs of each window (the fastest "
                    "counts; the answer is the first repeat's)")
    args = ap.parse_args()
    import tomllib

    with open(args.scene, "rb") as f:
        H = float(tomllib.load(f)["simulation"]["macro_step"])
    multiples = [int(x) for x in args.windows.split(",")]
    print("scene %s, case %s, H = %g s; the baseline: every cut at H; soil time = its static "
          "solves, its macro steps (its own clock); share = the soil's macro steps / the run's wall time; steps/ and share/: the baseline's over this run's" % (
              os.path.basename(args.scene), args.case, H), flush=True)
    print("%9s %6s %8s %8s %9s %6s %7s %7s %6s %-6s %6s %-28s %6s %s" % (
        "window s", "steps", "wall s", "statics", "stepping", "share", "steps/", "share/",
        "PPV dB", "at", "band dB", "at", "<=%gHz" % args.band_max, "at"), flush=True)
    # The repeats interleave every window, so that the machine's load
    # touches all of them alike; each time is the fastest of its repeats.
    best = {}
    for k in range(args.repeats):
        for m in [1] + multiples:
            r = run(args.master, args.scene, args.case, os.path.join(args.out, "%dH" % m), m * H)
            print("repeat %d: %s" % (k + 1, row(r, best.get(1, r), args)), file=sys.stderr,
                  flush=True)
            b = best.setdefault(m, r)
            for key in ("wall", "statics", "stepping"):
                b[key] = min(b[key], r[key])
    for b in best.values():
        b["share"] = b["stepping"] / b["wall"]
    for m in [1] + multiples:
        print(row(best[m], best[1], args), flush=True)


if __name__ == "__main__":
    main()
