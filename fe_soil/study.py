"""The study of a ground-vibration scene: what two-way coupling buys.

    /usr/bin/python3 -m fe_soil.study --scene SCENE --out OUT --master BIN/master

On a scene whose soil is the FE soil ([soil] model = "fe") it runs

- the co-simulation with the FE soil at the ss cut, three ways:
  ss-xt-jacobi, ss-xt-gauss-seidel (explicit coupling) and ss-xt-jacobi
  with --coupling implicit (the default accelerator, each macro step
  repeated until the exchanged values converge);
- the two-step method (fe_soil/two_step.py): the forces into the ballast of
  a monolithic run on a lumped soil fitted to the FE block's static
  stiffness, applied one way to the same FE block (in this process, which
  also writes the surface velocity snapshots: XDMF + HDF5 for ParaView);

times each one, runs a few fast checks, and writes OUT/REPORT.md (the
answer: free-field levels per distance, the difference two-way minus
two-step per band and distance, the cost of each method; the decay with
distance; the figures; the validation) and OUT/figures/*.png.
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

from .scene_file import read_scene
from . import config as fe_config
from . import measures, resolution, spectrum, two_step
from . import progress as fe_progress

# (key, label, case, extra options of master run)
COSIMS = [
    ("jacobi", "Jacobi", "ss-xt-jacobi", []),
    ("gauss-seidel", "Gauss-Seidel", "ss-xt-gauss-seidel", []),
    ("implicit", "implicit", "ss-xt-jacobi", ["--coupling", "implicit"]),
]
REFERENCE = "implicit"  # the two-way run the tables and the decay take as reference
ONE_WAY_CHECK_DOFS = 300_000  # above this the check's extra one-way run is left out


WINDOW_SUFFIX = "_macro_step"  # [coupling] CUT_macro_step: that cut's window (multirate)


class StudyError(Exception):
    pass


def cut_windows(table):
    """{cut: window in s} of the [coupling] table's CUT_macro_step keys."""
    return {k[: -len(WINDOW_SUFFIX)]: v for k, v in table.items() if k.endswith(WINDOW_SUFFIX)}


def window_options(windows):
    """master run's options that give each cut its window."""
    return [x for cut, w in sorted(windows.items()) for x in ("--macro-step", "%s=%r" % (cut, w))]


def load():
    return os.getloadavg()[0]


def read_vibration(path):
    """vibration.csv as a list of rows {column: float or str}."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [{k: (v if k == "receiver" else float(v)) for k, v in r.items()} for r in rows]


def run_master(master, scene, out, case, extra, progress=None):
    """One master run; (its folder, wall seconds, load at the start, its
    summary.json). Its output goes to OUT/master.log; its progress lines
    (once a second, or every RAILCOSIM_PROGRESS_SECONDS) move `progress` on."""
    t0, l0 = time.perf_counter(), load()
    cmd = [master, "run", "--scene", scene, "--case", case, "--out", out] + extra
    os.makedirs(out, exist_ok=True)
    log_path = os.path.join(out, "master.log")
    env = dict(os.environ, RAILCOSIM_PROGRESS_SECONDS=os.environ.get("RAILCOSIM_PROGRESS_SECONDS", "1"))
    with open(log_path, "w") as log:
        p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.PIPE, text=True, env=env)
        for line in p.stderr:
            m = fe_progress.STEP_LINE.match(line)
            if m and progress is not None:
                progress.at(int(m.group(1)), int(m.group(2)))
            if not line.startswith("progress: "):
                log.write(line)
                log.flush()
        p.wait()
    wall = time.perf_counter() - t0
    folder = os.path.join(out, case)
    if p.returncode != 0:
        with open(log_path) as f:
            text = f.read()
        raise StudyError("%s failed (exit %d); its output is in %s:\n%s"
                         % (" ".join(cmd), p.returncode, log_path, text[-2000:]))
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    if summary.get("status") != "ok":
        raise StudyError("%s ended with status %r: %s (%s)" % (
            " ".join(cmd), summary.get("status"), summary.get("message", ""),
            os.path.join(folder, "summary.json")))
    return folder, wall, l0, summary


class Snapshots:
    """After chosen steps of the one-way run: the velocity field into an
    XDMF file and the surface's vertical velocity into arrays (for the
    figure)."""

    def __init__(self, soil, path, steps, count):
        from . import snapshots

        self.steps = sorted({max(1, round(steps * (j + 1) / count)) for j in range(count)})
        self.xdmf = snapshots.open_xdmf(soil, path)
        nodes = soil.V.tabulate_dof_coordinates()[: soil.V.dofmap.index_map.size_local]
        self.surface = np.flatnonzero(nodes[:, 2] > -1e-6)
        self.xy = nodes[self.surface, :2]
        self.t, self.vz = [], []

    def __call__(self, k, soil):
        if k in self.steps:
            from . import snapshots

            snapshots.write_snapshot(soil, self.xdmf)
            self.t.append(soil.t)
            self.vz.append(soil.v[3 * self.surface + 2].copy())

    def save(self, path, receivers):
        self.xdmf.close()
        np.savez(path, x=self.xy[:, 0], y=self.xy[:, 1], t=np.array(self.t),
                 vz=np.array(self.vz), receivers=np.array(receivers))


def run_two_step(a, scene, out, reference_folder, names, xs, progress):
    """The two-step method; its folder (vibration.csv, receivers.csv like a
    co-simulation's), its costs, and what the checks need."""
    folder = os.path.join(out, "runs", "two-step")
    os.makedirs(folder, exist_ok=True)
    _, soil_csv = two_step.read_csv(os.path.join(reference_folder, "soil.csv"))
    t0, l0 = time.perf_counter(), load()
    soil, cfg = two_step.block(scene, soil_csv[:, 0])
    kf, kc = two_step.fit_lumped(soil, len(soil_csv))
    fit = time.perf_counter() - t0
    lumped = two_step.lumped_scene(a.scene, scene, cfg, kf, kc, os.path.join(out, "lumped.toml"))
    mono, lumped_wall, l1, _ = run_master(a.master, lumped, os.path.join(out, "runs", "lumped"),
                                          "monolithic", [], progress)
    _, forces = two_step.read_csv(os.path.join(mono, "soil_forces.csv"))
    t, H = forces[:, 0], float(forces[1, 0] - forces[0, 0])
    t1, l2 = time.perf_counter(), load()
    snaps = Snapshots(soil, os.path.join(folder, "velocity.xdmf"), len(t) - 1, a.snapshots)

    def after_step(k, s):
        snaps(k, s)
        progress.at(k, len(t) - 1)

    tr, v = two_step.one_way(soil, forces[:, 1:], t, H, after_step=after_step)
    one_way = time.perf_counter() - t1
    snaps.save(os.path.join(folder, "surface.npz"), soil.p.receivers)
    s = two_step.summaries(v, H)
    with open(os.path.join(folder, "vibration.csv"), "w") as f:
        f.write(measures.with_resolved(measures.vibration_csv(names, xs, cfg["receivers"], s),
                                       resolution.receiver_bands(soil, cfg, H * len(v))))
    with open(os.path.join(folder, "receivers.csv"), "w") as f:
        f.write(measures.receivers_csv(names, tr, v))
    cost = {"fit": fit, "lumped": lumped_wall, "one_way": one_way, "load": [l0, l1, l2]}
    return folder, cost, {"soil": soil, "forces": forces, "kf": kf, "kc": kc, "H": H,
                          "dofs": soil.global_dofs(), "lumped_scene": lumped}


def checks(runs, ts):
    """Fast checks, each (what, bound, measured, passed)."""
    out = []
    # The measures on a sine of amplitude A at a band centre (10 Hz) over 2 s
    # sampled at 1 kHz: its band level is 20 log10(A / sqrt 2 / 1e-9) dB.
    dt, A = 1e-3, 1e-4
    v = A * np.sin(2 * math.pi * 10.0 * np.arange(2000) * dt)
    fc, lv = measures.third_octave_levels(v, dt)
    err = abs(lv[int(np.argmin(abs(fc - 10.0)))] - 20 * math.log10(A / math.sqrt(2) / 1e-9))
    out.append(("one-third-octave level of a 10 Hz sine (closed form 20 log10(A/sqrt2/1e-9))",
                "<= 1e-9 dB", "%.1e dB" % err, err <= 1e-9))
    # KB_Fmax of an 8 Hz sine: KB/sqrt2 * sqrt(1 + 1/sqrt(1 + (2 w tau)^2)),
    # KB = 1e3 A / sqrt(1 + (f0/f)^2) (DIN 4150-2's weighting and time constant).
    dt, f = 2e-4, 8.0
    v = A * np.sin(2 * math.pi * f * np.arange(15000) * dt)
    kb = 1e3 * A / math.sqrt(1 + (measures.KB_F0 / f) ** 2)
    w = 2 * math.pi * f
    exact = kb / math.sqrt(2) * math.sqrt(1 + 1 / math.sqrt(1 + (2 * w * measures.KB_TAU) ** 2))
    rel = abs(measures.kb_fmax(v, dt) / exact - 1)
    out.append(("KB_Fmax of an 8 Hz sine against its closed form", "<= 0.5 %",
                "%.3f %%" % (100 * rel), rel <= 5e-3))
    # The implicit co-simulation converged at every macro step.
    it = runs["implicit"]["summary"].get("iterations", {})
    bad = it.get("not_converged_steps")
    out.append(("implicit co-simulation: macro steps that did not converge (tolerance 1e-8)",
                "0", "%s (mean %s, max %s iterations)" % (bad, it.get("mean"), it.get("max")),
                bad == 0))
    # The one-way machinery: driven by the forces the FE soil received in the
    # Jacobi run, held over each step as that schedule held them, the block
    # gives the Jacobi run's receivers back (the static state is solved
    # again, to 1e-12, hence not bitwise).
    what = "one-way run under the Jacobi run's received forces (held) against that run's receivers"
    folder = runs["jacobi"]["folder"]
    if ts["dofs"] > ONE_WAY_CHECK_DOFS:
        out.append((what, "<= 1e-7 of the peak", "not run: %d DOFs > %d (it costs one more "
                    "one-way run)" % (ts["dofs"], ONE_WAY_CHECK_DOFS), None))
    elif not os.path.exists(os.path.join(folder, "soil_forces.csv")):
        out.append((what, "<= 1e-7 of the peak", "not run: the scene does not write "
                    "soil_forces.csv ([output] ballast_forces = true)", None))
    else:
        # At the soil's window (multirate): the force at each window's start.
        w = runs["jacobi"]["windows"].get("ss")
        m = round(w / ts["H"]) if w else 1
        _, f = two_step.read_csv(os.path.join(folder, "soil_forces.csv"))
        _, rec = two_step.read_csv(os.path.join(folder, "receivers.csv"))
        _, v = two_step.one_way(ts["soil"], f[::m, 1:], f[::m, 0], m * ts["H"], hold=True)
        ref = rec[:, 1:].reshape(v.shape)
        err = float(np.abs(v - ref).max() / np.abs(ref).max())
        out.append((what, "<= 1e-7 of the peak", "%.1e" % err, err <= 1e-7))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True, help="a scene with [soil] model = \"fe\"")
    ap.add_argument("--out", required=True, help="the study's folder (REPORT.md, figures/, runs/)")
    ap.add_argument("--master", required=True, help="the master program (build/bin/master)")
    ap.add_argument("--snapshots", type=int, default=6,
                    help="surface velocity snapshots of the two-step run (default 6)")
    a = ap.parse_args(argv)
    scene = read_scene(a.scene, "fe", "; a scene on the lumped soil is studied by "
                       "`master study --scene %s`" % a.scene)
    windows = cut_windows(scene.get("coupling", {}))
    others = sorted(set(scene.get("coupling", {})) - {cut + WINDOW_SUFFIX for cut in windows})
    if others:
        sys.exit("%s: the scene has a [coupling] table, which sets how master run couples one "
                 "case; this study runs its own couplings and its runs would take the table's "
                 "values (%s): study a copy of the scene without it (the only keys it takes "
                 "are the cuts' windows, CUT%s)" % (a.scene, ", ".join(others), WINDOW_SUFFIX))
    if not os.access(a.master, os.X_OK):
        sys.exit("--master %s: not an executable (build it with scripts/build.sh: "
                 "build/bin/master)" % a.master)
    if a.snapshots < 1:
        sys.exit("--snapshots must be >= 1 (got %d)" % a.snapshots)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    out = os.path.abspath(a.out)
    shutil.rmtree(os.path.join(out, "runs"), ignore_errors=True)
    os.makedirs(out, exist_ok=True)
    try:
        cfg = fe_config.parse(scene["soil"])
    except fe_config.ConfigError as e:
        sys.exit("%s: %s" % (a.scene, e))
    started = time.perf_counter()
    runs = {}
    progress = fe_progress.Progress("ground-vibration study", len(COSIMS) + 1)
    try:
        for key, label, case, extra in COSIMS:
            extra = extra + window_options(windows)
            progress.say("study: %s (%s %s)" % (label, case, " ".join(extra)))
            progress.begin(label)
            folder, wall, l0, summary = run_master(a.master, a.scene,
                                                   os.path.join(out, "runs", key), case, extra,
                                                   progress)
            progress.run_done()
            runs[key] = {"label": label, "case": case, "extra": extra, "folder": folder,
                         "windows": windows,
                         "wall": wall, "load": l0, "summary": summary,
                         "vibration": read_vibration(os.path.join(folder, "vibration.csv"))}
        names = [r["receiver"] for r in runs["jacobi"]["vibration"]]
        xs = [r["x_m"] for r in runs["jacobi"]["vibration"]]
        progress.say("study: two-step method")
        progress.begin("two-step: the lumped run, then the FE soil one way")
        folder, cost, ts = run_two_step(a, scene, out, runs["jacobi"]["folder"], names, xs,
                                        progress)
        progress.run_done()
    except StudyError as e:
        progress.end()
        sys.exit(str(e))
    progress.end()
    runs["two-step"] = {"label": "two-step", "folder": folder, "cost": cost,
                        "wall": cost["fit"] + cost["lumped"] + cost["one_way"],
                        "load": cost["load"][0],
                        "vibration": read_vibration(os.path.join(folder, "vibration.csv"))}
    print("study: checks", flush=True)
    found = checks(runs, ts)
    from . import study_report

    info = {"scene": a.scene, "name": scene.get("scene", {}).get("name", a.scene),
            "distances": cfg["receivers"], "ranks": cfg["ranks"], "names": names, "H": ts["H"],
            "t_end": float(ts["forces"][-1, 0]), "dofs": ts["dofs"], "kf": ts["kf"],
            "kc": ts["kc"],
            "checks": found, "total": time.perf_counter() - started, "load": load(),
            "windows": windows}
    info["resolution"] = resolution.resolution(ts["soil"], cfg)
    info["load_content"] = spectrum.load_verdicts(
        ts["forces"][:, 1:], ts["H"], cfg["receivers"],
        [min(f, g) for _, f, g in info["resolution"][1]])
    study_report.write(out, runs, info)
    print("study: wrote %s" % os.path.join(out, "REPORT.md"), flush=True)


if __name__ == "__main__":
    main()
