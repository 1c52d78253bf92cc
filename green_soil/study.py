"""The study of a scene on the Green's-function soil: which soil it needs.

    /usr/bin/python3 -m green_soil.study --scene SCENE --out OUT --master BIN/master
                                         [--fe 'mesh_size = 1.0, depth = 6.0, margin = 2.0']

On a scene whose soil is the Green's-function soil ([soil] model = "green")
it runs the same vehicle and track on

- the Green's-function soil, two-way (master run --case ss-xt-jacobi);
- a lumped soil (a spring, dashpot and mass per sleeper, springs between
  neighbours) fitted to the layered ground's static flexibility under the
  footprints, run monolithically; its forces into the ballast go one way
  through the same Green's functions to the receivers (the two-step method:
  a lumped soil cannot give free-field levels by itself);
- with --fe, the FE soil two-way on the same layers and receivers, its mesh
  keys given by the option (a TOML inline table's content; the FE soil's
  [soil] keys, docs/fe-soil.md). Without it the FE soil is not run.

The most complete run is the reference: the FE soil's if it ran, else the
Green's-function soil's. OUT/REPORT.md holds the levels, the differences per
receiver and band, the cost of each run, the chart (OUT/figures/) and a
check; OUT/soil_choice.csv and .json the data (green_soil/soil_choice.py).
"""
import argparse
import json
import os
import re
import resource
import shutil
import sys
import time
import tomllib

import numpy as np

from fe_soil import measures, two_step
from fe_soil import study as fe_study
from fe_soil.config import channel_names
from fe_soil.scene_file import read_scene

from . import config as green_config
from . import outputs, resolution
from . import soil_choice
from .track import TrackSoil

CASE = "ss-xt-jacobi"


def cpu_seconds():
    """CPU seconds of this process and of its waited-for children so far."""
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


class Clock:
    """Wall and CPU seconds of the parts of one soil's run."""

    def __init__(self):
        self.parts, self.wall, self.cpu = {}, 0.0, 0.0

    def __call__(self, name, fn, *args, **kwargs):
        w0, c0 = time.perf_counter(), cpu_seconds()
        out = fn(*args, **kwargs)
        w, c = time.perf_counter() - w0, cpu_seconds() - c0
        self.parts[name] = w
        self.wall += w
        self.cpu += c
        return out


def scene_with_soil(scene_path, soil_table, path):
    """Writes to path the scene with its [soil] table (and its layers)
    replaced by soil_table (TOML text) and ballast forces written."""
    with open(scene_path) as f:
        text = f.read()
    text = re.sub(r"(?ms)^\[soil\].*?(?=^\[(?!\[soil\.))", "", text)
    text = text.replace("[output]", "[output_]")  # one [output] table, ours
    text = re.sub(r"(?ms)^\[output_\].*?(?=^\[|\Z)", "", text)
    with open(path, "w") as f:
        f.write(text + "\n" + soil_table + "\n[output]\nballast_forces = true\n")
    return path


def fe_table(scene, fe_keys):
    """The FE soil's [soil] table: the scene's layers and receivers, the
    mesh keys of --fe."""
    soil = scene["soil"]
    lines = ["[soil]", 'model = "fe"', "receivers = %s" % json.dumps(
        [float(r) for r in soil.get("receivers", green_config.DEFAULTS["receivers"])])]
    if "receiver_x" in soil:
        lines.append("receiver_x = %r" % float(soil["receiver_x"]))
    lines += ["%s = %s" % (k, json.dumps(v)) for k, v in fe_keys.items()]
    for layer in soil["layers"]:
        lines += ["", "[[soil.layers]]"] + ["%s = %r" % (k, float(v)) for k, v in layer.items()]
    return "\n".join(lines) + "\n"


def track_soil(scene, cfg, xs):
    """The Green's-function soil under footprints at xs, as the master
    describes them (one rail's share of a sleeper bay), with the scene's
    receivers."""
    spacing = scene["sleepers"]["spacing"]
    length = scene["sleepers"].get("length", 2.6)
    fps = [(x, length / 4.0, spacing, length / 2.0) for x in xs]
    H = soil_window(scene)
    rx = 0.5 * (min(xs) + max(xs)) if cfg["receiver_x"] is None else cfg["receiver_x"]
    memory = min(cfg["memory"], scene["simulation"]["end_time"] + H)
    r_memory = min(cfg["receiver_memory"], scene["simulation"]["end_time"] + H)
    soil = TrackSoil(cfg["layers"], fps, [(rx, d) for d in cfg["receivers"]], H, memory,
                     cfg["f_max"], workers=cfg["workers"], horizontal=True,
                     receiver_memory=r_memory)
    return soil, rx


def soil_window(scene):
    """The soil's macro step: the scene's [coupling] ss_macro_step, else H."""
    H = scene["simulation"]["macro_step"]
    return float(scene.get("coupling", {}).get("ss_macro_step", H))


def at_window(scene, rows):
    """The rows of a record written every H (its first row at t = 0) at
    the soil's window only: every k-th, k = window / H."""
    k = int(round(soil_window(scene) / scene["simulation"]["macro_step"]))
    return rows[::k]


def fit_lumped(soil):
    """(k_f, k_c) of the lumped soil with the layered ground's static
    stiffness under uniform footprint loads and under the middle footprint
    alone (fe_soil.two_step.fit_lumped's rule, on the elastic static
    flexibility of the Green's functions)."""
    flex = soil.elastic_static
    n = len(flex)

    class Static:
        def statics(self, f):
            return flex @ f

        def reset(self):
            pass

    return two_step.fit_lumped(Static(), n)


def one_way(soil, forces, hold=False):
    """The receivers' velocity rows [step, row] (vertical, then x, then y) under recorded
    forces[row, footprint] (linear between rows; hold: each row held over
    its step)."""
    soil.reset(forces[0])
    out = []
    for k in range(len(forces) - 1):
        _, _, r = soil.step(forces[k], forces[k] if hold else forces[k + 1])
        out.append(r)
    return np.array(out)


def write_receivers(folder, cfg, rx, rows, H):
    """vibration.csv and receivers.csv of a one-way run, as a co-simulation's."""
    names = channel_names(cfg["receivers"])
    v = outputs.components(rows, len(cfg["receivers"]))
    s = [measures.receiver_summary(v[:, k, :], H) for k in range(v.shape[1])]
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "vibration.csv"), "w") as f:
        f.write(outputs.vibration_csv(names, [rx] * len(names), cfg["receivers"], s,
                                      resolution.receiver_bands(cfg, H * len(v), H)))
    with open(os.path.join(folder, "receivers.csv"), "w") as f:
        f.write(measures.receivers_csv(names, H * np.arange(1, len(v) + 1), v))


def run(label, clock, master, scene, out, case):
    """One master run, timed on clock; its folder."""
    try:
        folder, _, _, _ = clock(label, fe_study.run_master, master, scene, out, case, [])
    except fe_study.StudyError as e:
        sys.exit(str(e))
    return folder


def green_two_way(a, out):
    clock = Clock()
    folder = run("master run --case %s" % CASE, clock, a.master, a.scene,
                 os.path.join(out, "runs", "green"), CASE)
    return folder, clock


def lumped_two_step(a, scene, cfg, out):
    """The lumped soil fitted to the Green's functions, run monolithically;
    its ballast forces one way through the Green's functions. (folder, clock,
    the check of the one-way machinery on the two-way run's own forces)."""
    clock = Clock()
    forces_path = os.path.join(out, "runs", "green", CASE, "soil_forces.csv")
    head, green_forces = two_step.read_csv(forces_path)
    xs = [float(x) for x in head[1:]]
    soil, rx = clock("Green's functions", track_soil, scene, cfg, xs)
    if soil.cache_hit:  # computed by the two-way run: read back
        clock.parts["Green's functions (cached)"] = clock.parts.pop("Green's functions")
    kf, kc = fit_lumped(soil)
    length = scene["sleepers"].get("length", 2.6)
    lumped = scene_with_soil(a.scene, two_step.lumped_table(
        {"layers": cfg["layers"]}, kf, kc, scene["sleepers"]["spacing"], length),
        os.path.join(out, "lumped.toml"))
    mono = run("lumped soil, monolithic", clock, a.master, lumped,
               os.path.join(out, "runs", "lumped"), "monolithic")
    _, forces = two_step.read_csv(os.path.join(mono, "soil_forces.csv"))
    vz = clock("one way through the Green's functions", one_way, soil,
               at_window(scene, forces[:, 1:]))
    folder = os.path.join(out, "runs", "two-step")
    write_receivers(folder, cfg, rx, vz, soil_window(scene))
    # The check: the two-way run's own forces, held, give its receivers back.
    _, rec = two_step.read_csv(os.path.join(out, "runs", "green", CASE, "receivers.csv"))
    again = outputs.components(one_way(soil, at_window(scene, green_forces[:, 1:]), hold=True),
                                   len(cfg["receivers"])).reshape(len(rec), -1)
    ref = rec[:, 1:]
    err = float(np.abs(again - ref).max() / np.abs(ref).max())
    return folder, clock, {"kf": kf, "kc": kc, "one_way_error": err}


def fe_two_way(a, scene, out):
    try:
        keys = tomllib.loads("fe = {%s}" % a.fe)["fe"]
    except tomllib.TOMLDecodeError as e:
        sys.exit("--fe %r: not the content of a TOML inline table (%s); e.g. --fe "
                 "'mesh_size = 1.0, depth = 6.0, margin = 2.0'" % (a.fe, e))
    path = scene_with_soil(a.scene, fe_table(scene, keys), os.path.join(out, "fe.toml"))
    clock = Clock()
    folder = run("master run --case %s" % CASE, clock, a.master, path,
                 os.path.join(out, "runs", "fe"), CASE)
    return folder, clock


def fe_resolved(scene, fe_keys, cfg):
    """{receiver distance: Hz}: the highest frequency the FE mesh of --fe
    holds with 10 elements per Rayleigh wavelength of the softest layer
    (its mesh-size rule, docs/fe-soil.md) at each receiver; 0
    beyond resolve_to on a graded mesh, whose elements grow there."""
    from fe_soil import config as fe_config
    from fe_soil.params import rayleigh_speed

    fe = fe_config.parse(tomllib.loads(fe_table(scene, tomllib.loads(
        "fe = {%s}" % fe_keys)["fe"]))["soil"])
    c = min(rayleigh_speed(l.shear_speed, l.poisson) for l in fe["layers"])
    h = fe["mesh_size"] or c / fe["f_max"] / fe["elements_per_wavelength"]
    out = {}
    for d in cfg["receivers"]:
        graded_beyond = fe["growth"] > 1.0 and d > fe["resolve_to"]
        out[d] = 0.0 if graded_beyond else c / (10.0 * h)
    return out


def entry(key, label, folder, clock, out):
    return {"key": key, "label": label, "folder": os.path.relpath(folder, out),
            "wall_s": clock.wall, "cpu_s": clock.cpu, "parts": clock.parts,
            "vibration": soil_choice.read_vibration(os.path.join(folder, "vibration.csv"))}


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True, help='a scene with [soil] model = "green"')
    ap.add_argument("--out", required=True, help="the study's folder (REPORT.md, figures/, runs/)")
    ap.add_argument("--master", required=True, help="the master program (build/bin/master)")
    ap.add_argument("--fe", metavar="KEYS",
                    help="also run the FE soil (python3-dolfinx) with these [soil] mesh keys, "
                         "e.g. 'mesh_size = 1.0, depth = 6.0, margin = 2.0'")
    a = ap.parse_args(argv)
    scene = read_scene(a.scene, "green", "; a scene on the FE soil is studied by `python3 -m "
                       "fe_soil.study`, one on the lumped soil by `master study`")
    other = sorted(set(scene.get("coupling", {})) - {"ss_macro_step"})
    if other:
        sys.exit("%s: [coupling] %s: this study runs its own couplings and takes only the "
                 "soil's window (ss_macro_step) from the scene: study a copy of the scene "
                 "without the other keys" % (a.scene, other[0]))
    if not os.access(a.master, os.X_OK):
        sys.exit("--master %s: not an executable (scripts/build.sh builds build/bin/master)"
                 % a.master)
    try:
        cfg = green_config.parse(scene["soil"])
    except green_config.ConfigError as e:
        sys.exit("%s: %s" % (a.scene, e))
    return a, scene, cfg


def main(argv=None):
    a, scene, cfg = parse_args(argv)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    out = os.path.abspath(a.out)
    shutil.rmtree(os.path.join(out, "runs"), ignore_errors=True)
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    print("study: the Green's-function soil, two-way", flush=True)
    folder, clock = green_two_way(a, out)
    soils = [entry("green", "Green's functions", folder, clock, out)]
    print("study: the lumped soil, two-step", flush=True)
    folder, clock, fit = lumped_two_step(a, scene, cfg, out)
    soils.insert(0, entry("lumped", "lumped (two-step)", folder, clock, out))
    if a.fe:
        print("study: the FE soil, two-way", flush=True)
        folder, clock = fe_two_way(a, scene, out)
        soils.append(entry("fe", "FE", folder, clock, out))
    reference = soils[-1]["key"]
    resolved = fe_resolved(scene, a.fe, cfg) if a.fe else None
    try:
        rows, summary = soil_choice.compare(soils, reference, "green" if a.fe else None,
                                            resolved)
    except ValueError as e:
        sys.exit("%s: %s" % (a.scene, e))
    res = [resolution.resolved(cfg, scene["simulation"]["end_time"], soil_window(scene), d)
           for d in cfg["receivers"]]
    summary["green_resolved_Hz"] = [[r["lo_Hz"], r["hi_Hz"]] for r in res]
    soil_choice.write_data(out, rows, summary)
    soil_choice.chart(os.path.join(out, "figures", "soil_choice.png"), summary)
    from . import study_report

    study_report.write(out, a, scene, soils, rows, summary, fit, res)
    print("study: wrote %s" % os.path.join(out, "REPORT.md"), flush=True)


if __name__ == "__main__":
    main()
