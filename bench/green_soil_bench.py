#!/usr/bin/env python3
"""The cost of the soil from Green's functions (green_soil/): the Green's
functions of the ground-vibration scene's layers (0 to f_max, footprint
distances to --reach m on both rails, receivers at 8 to 64 m), and the
participant's cost per macro step against the number of footprints (the
convolutions of track.TrackSoil.step, memory M steps, 256 steps: four
blocks of the partitioned convolution at M = 1000), partitioned and direct,
each the fastest of --repeats. Ratios are against the smallest N measured in the same run.

    /usr/bin/python3 bench/green_soil_bench.py [--greens] [--reach 200] [--f-max 100]
        [--steps 1000] [--counts 20 50 100] [--repeats 3] [--workers 1 2]
    /usr/bin/python3 bench/green_soil_bench.py --scene SCENE --forces SOIL_FORCES_CSV

With --scene (a scene with [soil] model = "green") and --forces (a run's
soil_forces.csv, whose header gives the footprints' positions): the soil
the participant builds for that scene, timed with an empty cache of
Green's functions and again from it, the vertical and horizontal tables
timed apart (ratio: the cached build against the first, same run).

The Green's functions are timed once per worker count (--workers, default
1 and the usable cores), ratios against the first count in the same run.
"""
import argparse
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from fe_soil.params import Layer  # noqa: E402
from green_soil import responses as R  # noqa: E402
from green_soil.track import TrackSoil  # noqa: E402

LAYERS = [Layer(1.4, 1800.0, 128.0, 0.375, 0.044), Layer(2.7, 1800.0, 176.0, 0.195, 0.038),
          Layer(1.0, 1800.0, 355.0, 0.478, 0.037)]  # scenes/ground_vibration.toml


def greens(reach, f_max, workers):
    n = int(reach / 0.6) + 1
    pairs = [(0.6 * k, 0.0) for k in range(n)] + [(0.6 * k, 1.3) for k in range(n)]
    points = [(0.0, d - 0.65) for d in (8.0, 16.0, 32.0, 64.0)] + \
             [(0.0, d + 0.65) for d in (8.0, 16.0, 32.0, 64.0)]
    rec = R.Record(dt=1e-3, duration=reach / 100.0 + 1.0, f_max=f_max)
    f, w = rec.frequencies()
    start = time.perf_counter()
    R.spectra(LAYERS, R.Footprint(0.6, 1.3), pairs, points, w, workers=workers)
    return len(pairs), len(points), len(w), time.perf_counter() - start


def per_step(n, steps, repeats, cache, block):
    fps = [(0.3 + 0.6 * k, 0.65, 0.6, 1.3) for k in range(n)]
    soil = TrackSoil(LAYERS, fps, [(0.3 * n, 8.0), (0.3 * n, 32.0)], 1e-4, steps * 1e-4,
                     f_max=100.0, cache_dir=cache, block=block)
    rng = np.random.default_rng(1)
    forces = 5e4 + 1e3 * rng.standard_normal((64, n))
    best = np.inf
    for _ in range(repeats):
        soil.reset(forces[0])
        start = time.perf_counter()
        for k in range(4 * 64):
            soil.step(forces[(k - 1) % 64], forces[k % 64])
        best = min(best, (time.perf_counter() - start) / (4 * 64))
    return best


def scene_build(scene_path, forces_path):
    """The scene's soil built twice (Green's functions computed, then
    cached): per build its wall time and the two tables' times."""
    import tomllib

    from fe_soil import two_step
    from green_soil import config, study

    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    cfg = config.parse(scene["soil"])
    head, _ = two_step.read_csv(forces_path)
    xs = [float(x) for x in head[1:]]
    clock = {}

    def timed(name, fn):
        def run(*args, **kwargs):
            start = time.perf_counter()
            out = fn(*args, **kwargs)
            clock[name] = clock.get(name, 0.0) + time.perf_counter() - start
            return out
        return run

    R.cached_spectra = timed("vertical", R.cached_spectra)
    R.cached_horizontal = timed("horizontal", R.cached_horizontal)
    with tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache
        first = None
        for label in ("computed", "cached"):
            clock.clear()
            start = time.perf_counter()
            soil, _ = study.track_soil(scene, cfg, xs)
            wall = time.perf_counter() - start
            first = first or wall
            print("%s: %d footprints, memory %d steps (receivers %d): built in %.1f s (%.2f x the "
                  "first); vertical Green's functions %.1f s, horizontal %.1f s"
                  % (label, soil.n, soil.M, soil.M_receivers, wall, wall / first,
                     clock["vertical"], clock["horizontal"]), flush=True)
            del soil


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", help="time the soil of this scene (needs --forces)")
    p.add_argument("--forces", help="a run's soil_forces.csv on that scene (the footprints)")
    p.add_argument("--greens", action="store_true")
    p.add_argument("--reach", type=float, default=200.0)
    p.add_argument("--f-max", type=float, default=100.0)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--counts", type=int, nargs="+", default=[20, 50, 100])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--workers", type=int, nargs="+", default=[1, R.usable_cores()],
                   help="worker processes for the Green's functions, each count timed once")
    a = p.parse_args()
    print("load average at start: %.1f" % os.getloadavg()[0])
    if a.scene or a.forces:
        if not (a.scene and a.forces):
            p.error("--scene and --forces go together")
        scene_build(a.scene, a.forces)
        print("load average at the end: %.1f" % os.getloadavg()[0])
        return
    if a.greens:
        serial = None
        for workers in a.workers:
            n_p, n_q, n_w, t = greens(a.reach, a.f_max, workers)
            serial = serial or t
            print("Green's functions: %d footprint offsets, %d receiver offsets, %d frequencies "
                  "to %g Hz, %d worker(s): %.1f s (%.2f x the first)"
                  % (n_p, n_q, n_w, a.f_max, workers, t, t / serial))
    with tempfile.TemporaryDirectory() as cache:
        base = None
        for n in a.counts:
            direct = per_step(n, a.steps, a.repeats, cache, 1)
            t = per_step(n, a.steps, a.repeats, cache, None)
            base = base or t
            print("N = %4d footprints, M = %d memory steps: %.3f ms per macro step partitioned "
                  "(%.1f x N = %d), direct sum %.3f ms (partitioned / direct %.2f)"
                  % (n, a.steps, 1e3 * t, t / base, a.counts[0], 1e3 * direct, t / direct))


if __name__ == "__main__":
    main()
