#!/usr/bin/python3
"""The footprints' own compliance (`[soil] footprint_compliance`,
fe_soil/near_field.py): what each way of computing the compliance the mesh
misses under a footprint gives, against the flexible rectangle's closed
form (homogeneous half-space) and against the scene block refined under the
loaded footprint (any soil), and what it costs.

The block is the scene keys' (the FE soil's own `config`, the default rule
f_max 20 Hz, `growth` 1.25, `static_reach` 5) under 21 sleepers' footprints
at 0.6 m, 10 kN on one of them; the soil is the homogeneous half-space
c_S = 100 m/s, rho = 2000, nu = 1/4 (0.25 x 2.5 m footprints) or the layers
of scenes/ground_vibration.toml (0.25 x 2.6 m). Printed per loaded
footprint, as a ratio to the reference:
  FE alone        the block's mean displacement without the correction;
  refined - coarse  + c_loc from the local block solved on the scene's
                  planes and refined under the footprint (the default);
  closed - coarse + c_loc from the closed form minus the local block on the
                  scene's planes extended by the static far field (the
                  homogeneous half-space only);
and the reference: the closed form, or the scene block itself with its
planes refined under the loaded footprint as the local block's are (the
fixture of tests/fe_soil/test_footprint_compliance.py).

Usage:  nice -n 10 bench/fe_footprint_bench.py [--soil homogeneous|layered] [--load 10 9]
"""
import argparse
import os
import sys
import time
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from fe_soil import config, far_field, near_field  # noqa: E402
from fe_soil.model import FESoil  # noqa: E402

F = 1e4  # N on the loaded footprint
HOMOGENEOUS = [{"density": 2000.0, "shear_wave_speed": 100.0, "poisson": 0.25}]
LAYERED = [{"thickness": 1.4, "density": 1800.0, "shear_wave_speed": 128.0, "poisson": 0.375},
           {"thickness": 2.7, "density": 1800.0, "shear_wave_speed": 176.0, "poisson": 0.195},
           {"density": 1800.0, "shear_wave_speed": 355.0, "poisson": 0.478}]


def block(layers, width, compliance, f_max=20.0):
    table = {"model": "fe", "f_max": f_max, "growth": 1.25, "receivers": [4.0, 8.0],
             "layers": layers, "footprint_compliance": compliance}
    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=width, y=0.0) for i in range(21)]
    return config.block_params(config.parse(table), sleepers)[0]


def refined_scene(p, k):
    """The scene block's planes with the window of footprint k's local
    block replaced by the refined local block's (the same refinement)."""
    fp = p.footprints[k]
    nodes = (p.x_nodes, p.y_nodes, p.z_nodes)
    local = near_field.local_block(p, nodes, fp)
    fine = near_field.refined_block(local)
    shift = (fp.x, 0.0, 0.0)
    out = []
    for axis, (planes, lo, hi, ref) in enumerate(zip(
            nodes, (local.x[0], local.y[0], local.z[0]), (local.x[-1], local.y[-1], local.z[-1]),
            (fine.x, fine.y, fine.z))):
        lo, hi = lo + shift[axis], hi + shift[axis]
        keep = [v for v in planes if v < lo - 1e-9 or v > hi + 1e-9]
        out.append(sorted(keep + [v + shift[axis] for v in ref]))
    p.x_nodes, p.y_nodes, p.z_nodes = out
    return p


def closed_minus_coarse(p, k):
    """c_loc by the closed form minus the local block on the scene's planes
    extended by the static far field (grown by 2 to 5 times its extent)."""
    local = near_field.local_block(p, (p.x_nodes, p.y_nodes, p.z_nodes), p.footprints[k])
    extent = max(local.x[-1] - local.x[0], local.y[-1], -local.z[0])
    (ex, ey, ez), _ = far_field.extended_nodes((local.x, local.y, local.z), 5.0 * extent,
                                               local.symmetric, 0.0)
    grown = near_field.LocalBlock(ex, ey, ez, local.symmetric, local.footprint, local.interfaces)
    closed = near_field.flexible_rectangle(p.layers[0], local.footprint.along,
                                           local.footprint.across)
    return closed - near_field.mean_compliance(p, grown)


def statics(soil, k):
    forces = np.zeros(len(soil.p.footprints))
    forces[k] = F
    return soil.statics(forces)[k] / F


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--soil", choices=("homogeneous", "layered"), default="homogeneous")
    ap.add_argument("--load", type=int, nargs="+", default=[10])
    args = ap.parse_args()
    layers, width = (HOMOGENEOUS, 2.5) if args.soil == "homogeneous" else (LAYERED, 2.6)
    t0 = time.perf_counter()
    soil = FESoil(block(layers, width, True))
    t1 = time.perf_counter()
    print(f"{args.soil}: {soil.global_dofs()} DOFs; set-up {t1 - t0:.1f} s with the local problems")
    for k in args.load:
        c = soil.fp_compliance[k]
        raw = statics(soil, k) - c
        t2 = time.perf_counter()
        b = closed_minus_coarse(soil.p, k) if args.soil == "homogeneous" else float("nan")
        t3 = time.perf_counter()
        if args.soil == "homogeneous":
            ref, what = near_field.flexible_rectangle(soil.p.layers[0], 0.25, width), "closed form"
        else:
            fine = FESoil(refined_scene(block(layers, width, False), k))
            ref, what = statics(fine, k), f"refined block ({fine.global_dofs()} DOFs)"
        print(f"footprint {k}: reference {what} {ref:.7e} m/N; FE alone {raw / ref:.4f}, "
              f"refined - coarse {(raw + c) / ref:.4f} (c_loc {c / ref:.4f}), closed - coarse "
              f"{(raw + b) / ref:.4f} ({t3 - t2:.1f} s)", flush=True)


if __name__ == "__main__":
    main()
