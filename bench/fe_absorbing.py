#!/usr/bin/python3
"""The FE soil's whole record against Lamb's problem: what comes back from
the block's boundary and its graded mesh.

The homogeneous half-space (c_S = 100 m/s, rho = 2000, nu = 1/4, no
damping) under the ground-vibration scene's [soil] keys (the graded rule:
f_max, elements_per_wavelength (default 12), growth, resolve_to, margin,
depth, receivers), 21 sleepers' 0.25 x 2.5 m footprints 0.6 m apart, a
Ricker force on the middle one. Each receiver's vertical velocity over the
whole record (from the load's start to --t-end) against the closed form of
Pekeris averaged over the footprint (fe_soil/record_check.py): normalised
RMS, PPV, KB_Fmax and band levels up to f_max (the bands within 30 dB of
the record's highest), and over the direct waves the arrival, the peak and
the normalised RMS.

Usage:  nice -n 10 bench/fe_absorbing.py [--f-max 10] [--fc 7.5] [--growth 1.25]
            [--set KEY=VALUE ...] [--param FIELD=LITERAL ...] [--bands] [--png FILE]
            [--save FILE.npz]
        nice -n 10 bench/fe_absorbing.py --scene-cost scenes/ground_vibration.toml
            --baseline growth=1.25,fine_depth=0,absorbing_reflection=1
One row per receiver; --set absorbing_reflection=1 --growth 1.25 is the old
mesh and boundary. --param sets a SoilParams field after the keys (e.g.
spring_alpha=(0.0,0.0): dashpots alone on the outer boundary); --save keeps
t and each judged receiver's FE and reference records for a closer look.
"""
import argparse
import ast
import math
import os
import sys
import time
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from fe_soil import config, record_check  # noqa: E402

RHO, CS, NU = 2000.0, 100.0, 0.25
FORCE, MIDDLE, SLEEPERS = 1e4, 10, 21


def table(args, baseline=False):
    t = {"model": "fe", "f_max": args.f_max, "growth": args.growth,
         "receivers": [float(r) for r in args.receivers.split(",")],
         "resolve_to": args.resolve_to, "static_reach": 0.0,
         "layers": [{"density": RHO, "shear_wave_speed": CS, "poisson": NU}]}
    for kv in (args.baseline.split(",") if baseline else args.set):
        k, v = kv.split("=", 1)
        t[k] = float(v)
    return t


def run(args, baseline=False):
    """(soil, params, times, downward velocity per receiver, seconds)."""
    from fe_soil.model import FESoil

    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0) for i in range(SLEEPERS)]
    p = config.block_params(config.parse(table(args, baseline)), sleepers)[0]
    for kv in ([] if baseline else args.param):
        k, v = kv.split("=", 1)
        setattr(p, k, ast.literal_eval(v))
    t_start = time.perf_counter()
    soil = FESoil(p)
    f = record_check.lamb.ricker(args.fc, args.t0)[0]
    forces = np.zeros((2, SLEEPERS))
    H = soil.dt
    for k in range(int(math.ceil(args.t_end / H))):
        forces[0, MIDDLE], forces[1, MIDDLE] = FORCE * f(k * H), FORCE * f((k + 1) * H)
        soil.advance(k * H, H, forces[0], forces[1])
    t, v = soil.receiver_series()
    return soil, p, t, -v[:, :, 2], time.perf_counter() - t_start


def scene_cost(args):
    """The block of a scene's [soil] table (under --sleepers footprints),
    as it stands and with --baseline's keys: DOFs, the stable step and the
    fastest of three runs of --steps steps, alternately in this run."""
    import tomllib

    from fe_soil.model import FESoil

    with open(args.scene_cost, "rb") as f:
        soil_table = tomllib.load(f)["soil"]
    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0)
                for i in range(args.sleepers)]
    soils = {}
    for name, keys in (("scene", []), ("baseline", (args.baseline or "").split(","))):
        t = dict(soil_table)
        t.update({k: float(v) for k, v in (kv.split("=", 1) for kv in keys if kv)})
        soils[name] = FESoil(config.block_params(config.parse(t), sleepers)[0])
    best = {name: math.inf for name in soils}
    for _ in range(3):
        for name, soil in soils.items():
            f0 = soil.load_vector(np.full(args.sleepers, 1e4))
            t0 = time.perf_counter()
            soil.run(soil.dt, args.steps, f0, 0.0 * f0)
            best[name] = min(best[name], time.perf_counter() - t0)
    for name, soil in soils.items():
        print("%-8s %8d DOFs, dt %.4f ms, %.2f ms a step (%.2f x the baseline's)" % (
            name, soil.global_dofs(), soil.dt * 1e3, best[name] / args.steps * 1e3,
            best[name] / best["baseline"]))


def measure(args, soil, p, t, v, wall, title):
    """Prints a row per judged receiver; returns (distance, reference, measures)."""
    onset = args.t0 - 1.0 / args.fc
    extents = (p.length, p.half_width, p.depth)  # the direct waves: before the block's echo
    fp = p.footprints[MIDDLE]
    print("%s: f_max %g Hz, Ricker %g Hz: %d DOFs, dt %.3f ms, %d steps, %.1f s"
          % (title, args.f_max, args.fc, soil.global_dofs(), soil.dt * 1e3, len(t), wall))
    print("%5s %7s %7s %7s %7s %9s | %8s %7s %7s" % ("r m", "nRMS", "PPV", "KB", "band dB",
                                                      "at Hz", "arrival", "peak", "nRMS d"))
    rows = []
    judged = [float(r) for r in args.judged.split(",")]
    for i, (x, y) in enumerate(p.receivers):
        if y not in judged:
            continue
        ref = record_check.footprint_reference(t, (x, y), (fp.x, fp.y, fp.along, fp.across),
                                               RHO * CS * CS, CS, FORCE, args.fc, args.t0)
        m = record_check.compare(t, v[:, i], ref, args.t0,
                                 record_check.direct_end(onset, y, extents, CS), args.f_max)
        rows.append((y, ref, m, v[:, i], t))
        if args.bands:
            print("      bands", " ".join("%.3g:%+.2f" % b for b in zip(*m["bands"])))
        print("%5g %7.3f %+7.3f %+7.3f %7.2f %9.3g | %+8.4f %+7.3f %7.3f" % (
            y, m["nrms"], m["ppv"], m["kb"], m["band_db"], m["band_at"], m["arrival"], m["peak"],
            m["direct_nrms"]), flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--f-max", type=float, default=10.0)
    ap.add_argument("--fc", type=float, default=7.5, help="Hz, the Ricker's centre frequency")
    ap.add_argument("--t0", type=float, default=None, help="s, its peak (default 1.2/fc)")
    ap.add_argument("--t-end", type=float, default=0.6, help="s, the record's end")
    ap.add_argument("--growth", type=float, default=1.1)
    ap.add_argument("--resolve-to", type=float, default=16.0)
    ap.add_argument("--receivers", default="4,8,16,32")
    ap.add_argument("--judged", default="4,8,16", help="receivers compared (m)")
    ap.add_argument("--set", action="append", default=[], help="another [soil] key=number")
    ap.add_argument("--param", action="append", default=[],
                    help="a SoilParams field=Python literal, set after the [soil] keys")
    ap.add_argument("--save", default=None, help="an .npz of t, the FE and reference records")
    ap.add_argument("--bands", action="store_true", help="print each band's difference")
    ap.add_argument("--baseline", default=None, help="key=number,...: a second run on other "
                    "keys, measured and drawn beside (e.g. growth=1.25,fine_depth=0,"
                    "absorbing_reflection=1: the previous rule)")
    ap.add_argument("--png", default=None, help="a figure of the records, FE against Pekeris")
    ap.add_argument("--scene-cost", default=None, help="a scene: time its block's steps "
                    "against --baseline's keys instead")
    ap.add_argument("--sleepers", type=int, default=123, help="with --scene-cost: footprints")
    ap.add_argument("--steps", type=int, default=50, help="with --scene-cost: steps timed")
    args = ap.parse_args()
    if args.scene_cost:
        return scene_cost(args)
    args.t0 = 1.2 / args.fc if args.t0 is None else args.t0
    rows = measure(args, *run(args), "growth %g %s" % (args.growth, " ".join(args.set + args.param)))
    if args.save:
        np.savez(args.save, t=rows[0][4], fe=np.array([r[3] for r in rows]),
                 ref=np.array([r[1] for r in rows]), r=np.array([r[0] for r in rows]))
    old = None
    if args.baseline:
        old = measure(args, *run(args, True), "baseline %s" % args.baseline)
    if args.png:
        figure(args.png, rows, old, args)


def figure(path, rows, old, args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(rows), 1, figsize=(7.0, 1.8 * len(rows)), sharex=True)
    axes = np.atleast_1d(axes)
    for k, (ax, (y, ref, m, v, t)) in enumerate(zip(axes, rows)):
        if old is not None:
            ax.plot(old[k][4], old[k][3] * 1e3, color="0.6", lw=0.8,
                    label="FE, baseline (nRMS %.2f)" % old[k][2]["nrms"])
        ax.plot(t, ref * 1e3, "k-", lw=1.2, label="Pekeris (closed form)")
        ax.plot(t, v * 1e3, "r--", lw=1.0, label="FE")
        ax.set_ylabel("%g m: v_z mm/s" % y, fontsize=8)
        ax.set_title("%g m: nRMS %.3f, PPV %+.1f %%, KB_Fmax %+.1f %%" % (
            y, m["nrms"], 100 * m["ppv"], 100 * m["kb"]), fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=6, loc="upper right")
    axes[-1].set_xlabel("t (s)", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=72)


if __name__ == "__main__":
    main()
