"""The load of the soil studies (fe_soil/mitigation.py, fe_soil/ground_study.py):
one load drives every variant, so that what differs between two records is
the measure or the ground, not the source.

    [soil.mitigation]
    load = "ricker"     # or "train"
    duration = 0.4      # s, the record (both loads)
    # the Ricker force's keys (refused with load = "train"):
    sleepers = 25       # footprints at [sleepers] spacing
    frequency = 15.0    # Hz: the centre of a Ricker force on the middle one
    amplitude = 1e4     # N, its peak (at 1.2 / frequency)
    step = 2e-3         # s, the record's sampling (the soil steps below it)

"ricker": a Ricker force on the middle one of `sleepers` footprints.

"train": the scene's own vehicle (a car or a whole train) on its own track,
by the two-step method (fe_soil/two_step.py): the master runs the vehicle
and track monolithically over `duration` s on a lumped soil fitted to the
reference variant's static stiffness under the track's footprints, and
the forces into the ballast under every sleeper (soil_forces.csv) are then
applied one way to each variant's block, at every sleeper of the track,
every [simulation] macro_step. The variants feel the same train; a measure's
effect on the forces themselves is left out (the measure stands away from
the track; say so wherever the numbers are used).
"""
import json
import math
import os
import re
import subprocess
import tomllib

import numpy as np

from . import soil_table, two_step
from .soil_table import ConfigError

KINDS = ("ricker", "train")
# key: (default, lower bound (refused itself), upper bound (refused itself))
RICKER_KEYS = {"sleepers": (25, 0, 401), "frequency": (15.0, 0.1, 500.0),
               "amplitude": (1e4, 1e-3, 1e9), "step": (2e-3, 1e-5, 0.05)}
DURATION = (0.4, 0.0, 60.0)
MIN_SAMPLES = 10  # the record holds at least this many steps


def load_keys(table):
    """The checked [soil.mitigation] keys as a dict (kind, duration and, for
    the Ricker force, its keys)."""
    table = table or {}
    if not isinstance(table, dict):
        raise ConfigError("[soil] mitigation must be a table ([soil.mitigation])")
    known = set(RICKER_KEYS) | {"load", "duration"}
    unknown = sorted(set(table) - known)
    if unknown:
        raise ConfigError("[soil] mitigation.%s is not a key of [soil.mitigation] (its keys: %s)"
                          % (unknown[0], ", ".join(sorted(known))))
    kind = table.get("load", "ricker")
    if kind not in KINDS:
        raise ConfigError("[soil] mitigation.load must be one of %s (got %r)"
                          % (", ".join('"%s"' % k for k in KINDS), kind))
    out = {"load": kind, "duration": soil_table.number(
        table, "duration", "mitigation.", lo=DURATION[1], hi=DURATION[2], default=DURATION[0])}
    if kind == "train":
        given = sorted(set(table) & set(RICKER_KEYS))
        if given:
            raise ConfigError("[soil] mitigation.%s is a key of the Ricker force: with load = "
                              "\"train\" the forces come from the scene's train, every "
                              "[simulation] macro_step at every sleeper" % given[0])
        return out
    for key, (default, lo, hi) in RICKER_KEYS.items():
        out[key] = soil_table.number(table, key, "mitigation.", lo=lo, hi=hi, default=default)
    if out["sleepers"] != int(out["sleepers"]):
        raise ConfigError("[soil] mitigation.sleepers must be a whole number (got %g)"
                          % out["sleepers"])
    out["sleepers"] = int(out["sleepers"])
    if out["duration"] < MIN_SAMPLES * out["step"]:
        raise ConfigError("[soil] mitigation.duration %g s holds fewer than %d steps of %g s "
                          "([soil] mitigation.step)" % (out["duration"], MIN_SAMPLES, out["step"]))
    return out


class Ricker:
    """A Ricker force on the middle footprint, from rest."""

    def __init__(self, scene, load):
        from .mitigation import footprints

        self.load = load
        self.footprints = footprints(scene, load["sleepers"])
        self.dt = load["step"]

    def force(self, t):
        fc = self.load["frequency"]
        a = (math.pi * fc * (t - 1.2 / fc)) ** 2
        out = np.zeros(len(self.footprints))
        out[len(out) // 2] = self.load["amplitude"] * (1.0 - 2.0 * a) * math.exp(-a)
        return out

    def drive(self, soil):
        """(t, v[time, receiver, component]) every dt."""
        H = self.dt
        soil.reset()
        for k in range(int(round(self.load["duration"] / H))):
            soil.advance(k * H, H, self.force(k * H), self.force((k + 1) * H))
        return soil.receiver_series()

    def text(self):
        ld = self.load
        return ("a Ricker force of %g N peaking at %.3g s, centre %g Hz, on the middle one of %d "
                "footprints, recorded over %g s every %g s" % (
                    ld["amplitude"], 1.2 / ld["frequency"], ld["frequency"], ld["sleepers"],
                    ld["duration"], ld["step"]))


def toml_text(table, prefix=""):
    """A TOML text of a table read by tomllib (scalars, arrays, tables and
    arrays of tables; JSON's numbers, strings and booleans are TOML's)."""
    lines, subs = [], []
    for k, v in table.items():
        if isinstance(v, dict):
            subs.append(("[%s%s]" % (prefix, k), v, prefix + k + "."))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            subs += [("[[%s%s]]" % (prefix, k), x, prefix + k + ".") for x in v]
        else:
            key = k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)
            lines.append("%s = %s" % (key, json.dumps(v)))
    for head, sub, pre in subs:
        lines += ["", head, toml_text(sub, pre)]
    return "\n".join(lines)


class Train:
    """The scene's train on its track: the forces into the ballast of a
    monolithic run on a fitted lumped soil, applied one way to every block."""

    def __init__(self, scene, load, cfg, reference_block, master, out):
        """reference_block(footprints): the FESoil the lumped soil is fitted
        to; master: the master program; out: where the lumped runs go."""
        if not master or not os.path.isfile(master):
            raise ConfigError("[soil] mitigation.load = \"train\" runs the scene's train with "
                              "the master program: give it (--master BIN/master; not found: %s)"
                              % master)
        self.scene, self.load, self.master = scene, load, master
        self.folder = os.path.join(out, "train")
        os.makedirs(self.folder, exist_ok=True)
        sim = scene.get("simulation", {})
        self.dt = float(sim.get("macro_step", 0.0))
        if not self.dt > 0.0 or load["duration"] < MIN_SAMPLES * self.dt:
            raise ConfigError("[soil] mitigation.duration %g s holds fewer than %d macro steps "
                              "of %g s ([simulation] macro_step)"
                              % (load["duration"], MIN_SAMPLES, self.dt))
        # The track's sleepers: a first run on any lumped soil (the track's
        # length follows the run's end time where its count is "auto").
        xs = self._positions(load["duration"])
        spacing = scene["sleepers"]["spacing"]
        length = scene["sleepers"].get("length", 2.6)
        from railcosim_sdk import Footprint

        self.footprints = [Footprint(x, length / 4.0, 0.0, spacing, length / 2.0) for x in xs]
        soil = reference_block(self.footprints)
        self.kf, self.kc = two_step.fit_lumped(soil, len(xs))
        lumped = tomllib.loads(two_step.lumped_table(cfg, self.kf, self.kc, spacing, length))
        self.t, self.forces = self._run(lumped["soil"], load["duration"], "lumped")
        if self.forces.shape[1] != len(xs):
            raise ConfigError("the train's run has %d sleepers where its first step had %d"
                              % (self.forces.shape[1], len(xs)))

    def _scene(self, soil, end_time, name):
        s = {k: v for k, v in self.scene.items() if k not in ("soil", "output")}
        s["simulation"] = dict(self.scene.get("simulation", {}), end_time=end_time)
        s["soil"] = soil
        s["output"] = {"ballast_forces": True}
        path = os.path.join(self.folder, name + ".toml")
        with open(path, "w") as f:
            f.write("# The train's run of the soil study (fe_soil/study_load.py)\n")
            f.write(toml_text(s) + "\n")
        return path

    def _run(self, soil, end_time, name):
        path = self._scene(soil, end_time, name)
        out = os.path.join(self.folder, name)
        p = subprocess.run([self.master, "run", "--scene", path, "--case", "monolithic",
                            "--out", out], capture_output=True, text=True)
        if p.returncode != 0:
            raise ConfigError("the train's run (%s run --scene %s --case monolithic) failed:\n%s"
                              % (self.master, path, (p.stdout + p.stderr).strip()))
        head, data = two_step.read_csv(os.path.join(out, "monolithic", "soil_forces.csv"))
        self.positions = [float(x) for x in head[1:]]
        return data[:, 0], data[:, 1:]

    def _positions(self, end_time):
        probe = {"model": "lumped", "stiffness": 1e8, "damping": 1e5, "mass": 1e3,
                 "coupling_stiffness": 0.0, "coupling_damping": 0.0}
        self._run(probe, end_time, "positions")
        return list(self.positions)

    def drive(self, soil):
        """(t, v[time, receiver, component]) every macro step: statics under
        the first row, then the rows linear in between."""
        return two_step.one_way(soil, self.forces, self.t, self.dt)

    def text(self):
        v = self.scene.get("vehicle", {})
        return ("the scene's %s at %g km/h on its track, by the two-step method: the forces into "
                "the ballast under each of its %d sleepers from a monolithic run on a lumped soil "
                "fitted to the reference's static stiffness (k_f = %.4g N/m, k_c = %.4g N/m), "
                "applied one way to every variant from the static state, recorded over %g s "
                "every %g s" % (v.get("model", "vehicle"), v.get("speed_kmh", float("nan")),
                                len(self.footprints), self.kf, self.kc, self.load["duration"],
                                self.dt))


def make(scene, load, cfg, reference_block, master, out):
    """The study's load: Ricker or Train."""
    if load["load"] == "train":
        return Train(scene, load, cfg, reference_block, master, out)
    return Ricker(scene, load)
