"""The load of the soil studies (fe_soil/mitigation.py, fe_soil/ground_study.py):
one load drives every variant, so that what differs between two records is
the measure or the ground, not the source.

    [soil.mitigation]
    load = "ricker"     # or "train"
    duration = 0.4      # s, the record (both loads)
    track_window = 60.0 # m, train only, optional: the block carries the
                        # sleepers within half of it of the track's middle
    # the Ricker force's keys (refused with load = "train"):
    sleepers = 25       # footprints at [sleepers] spacing
    frequency = 15.0    # Hz: the centre of a Ricker force on the middle one
    amplitude = 1e4     # N, its peak (at 1.2 / frequency)
    step = 2e-3         # s, the record's sampling (the soil steps below it)

"ricker": a Ricker force on the middle one of `sleepers` footprints.

"train": the scene's own vehicle (a car or a train, with its rail
roughness) on its own track, by the two-step method (fe_soil/two_step.py):
the master runs the vehicle and track monolithically over `duration` s on
a lumped soil fitted to a block's static stiffness under the track's
footprints (the stiffness at the middle one, every footprint loaded alike:
it depends on how many there are, and the track's length follows
`duration` where its count is "auto"), and the forces into the ballast
under every sleeper (soil_forces.csv) are applied one way, every
[simulation] macro_step, from the static state. Every sleeper of the track
is a footprint of the FE block (at most MAX_FOOTPRINTS), the receivers
beside the middle one; with track_window only those around the middle,
the others' forces left out (a long train on a block of its own length
would be too large). The insertion-loss study fits to the reference
block and drives every variant with the same forces (a measure's effect on
them is left out: it stands away from the track); the ground shapes'
comparison fits to each ground's own block, which carries the track.
"""
import math
import os
import subprocess
import tomllib

import numpy as np

from . import scene_file, soil_table, two_step
from .soil_table import ConfigError

KINDS = ("ricker", "train")
# key: (default, lower bound (refused itself), upper bound (refused itself))
RICKER_KEYS = {"sleepers": (25, 0, 401), "frequency": (15.0, 0.1, 500.0),
               "amplitude": (1e4, 1e-3, 1e9), "step": (2e-3, 1e-5, 0.05)}
DURATION = (0.4, 0.0, 60.0)
MIN_SAMPLES = 10  # the record holds at least this many steps
TRACK_WINDOW_MAX = 1e4  # m: the bound of [soil.mitigation] track_window (refused itself)


def load_keys(table):
    """The checked [soil.mitigation] keys as a dict (kind, duration and, for
    the Ricker force, its keys)."""
    table = table or {}
    if not isinstance(table, dict):
        raise ConfigError("[soil] mitigation must be a table ([soil.mitigation])")
    known = set(RICKER_KEYS) | {"load", "duration", "track_window"}
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
        out["track_window"] = (soil_table.number(table, "track_window", "mitigation.", lo=0.0,
                                                 hi=TRACK_WINDOW_MAX)
                               if "track_window" in table else None)
        return out
    if "track_window" in table:
        raise ConfigError("[soil] mitigation.track_window is a key of the train's load "
                          "(load = \"train\"): the Ricker force has its own sleepers")
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

    def take_block(self):  # no block was built for it
        return None

    def __init__(self, scene, load):
        self.load = load
        spacing = scene["sleepers"]["spacing"]
        self.footprints = two_step.footprints(scene,
                                              [spacing * i for i in range(load["sleepers"])])
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


MAX_FOOTPRINTS = 400  # the Ricker's bound on footprints, the train's too


class Train:
    """The scene's vehicle on its track: the forces into the ballast of a
    monolithic run on a lumped soil fitted to a block, applied one way."""

    def __init__(self, scene, load, cfg, block, master, out, scene_dir=".", keep=False):
        """block(footprints): the FESoil the lumped soil is fitted to, kept
        for `take_block` if `keep` (its static solutions dropped, so that a
        run on it starts its statics from zero as on a fresh block); master:
        the master program; out: where the train's runs go; scene_dir: the
        folder the scene's relative file names are read from."""
        if not master or not os.path.isfile(master):
            raise ConfigError("[soil] mitigation.load = \"train\" runs the scene's vehicle with "
                              "the master program: give it with --master BIN/master%s"
                              % ("" if not master else " (not found: %s)" % master))
        if "fmu" in scene.get("vehicle", {}):
            raise ConfigError("[soil] mitigation.load = \"train\" runs the vehicle "
                              "monolithically, which a [vehicle.fmu] cannot: use load = "
                              "\"ricker\"")
        self.scene, self.load, self.master, self.scene_dir = scene, load, master, scene_dir
        self.folder = out
        os.makedirs(self.folder, exist_ok=True)
        self.dt = float(scene.get("simulation", {}).get("macro_step", 0.0))
        steps = load["duration"] / self.dt if self.dt > 0.0 else 0.0
        if steps < MIN_SAMPLES or abs(steps - round(steps)) > 1e-9 * steps:
            raise ConfigError("[soil] mitigation.duration %g s must be a whole number of at "
                              "least %d macro steps of %g s ([simulation] macro_step): it is "
                              "the end time of the vehicle's run" % (
                                  load["duration"], MIN_SAMPLES, self.dt))
        # The track's sleepers: a first run on any lumped soil (the track's
        # length follows the run's end time where its count is "auto").
        probe = {"model": "lumped", "stiffness": 1e8, "damping": 1e5, "mass": 1e3,
                 "coupling_stiffness": 0.0, "coupling_damping": 0.0}
        xs, _, _ = self._run(probe, "positions")
        self.track = len(xs)
        self.window = self._window(xs, load.get("track_window"))
        if len(self.window) > MAX_FOOTPRINTS:
            raise ConfigError("[soil] mitigation.load = \"train\": the vehicle's track over "
                              "[soil] mitigation.duration = %g s has %d sleepers%s, each a "
                              "footprint of the FE block, more than %d: shorten the duration "
                              "(or the vehicle), or give [soil] mitigation.track_window, the "
                              "length of track around the receivers the block carries" % (
                                  load["duration"], len(self.window),
                                  "" if len(self.window) == len(xs) else " in its track_window",
                                  MAX_FOOTPRINTS))
        self.footprints = two_step.footprints(scene, [xs[i] for i in self.window])
        fitted = block(self.footprints)
        self.kf, self.kc = two_step.fit_lumped(fitted, len(self.window))
        self._block = fitted if keep else None
        del fitted
        spacing = scene["sleepers"]["spacing"]
        lumped = tomllib.loads(two_step.lumped_table(cfg, self.kf, self.kc, spacing,
                                                     scene["sleepers"].get("length", 2.6)))
        at, self.t, self.forces = self._run(lumped["soil"], "lumped")
        if not np.allclose(at, xs, rtol=0.0, atol=1e-9):
            raise ConfigError("the vehicle's run on the fitted soil has other sleepers (%d) "
                              "than its first run (%d)" % (len(at), len(xs)))
        if not np.allclose(np.diff(self.t), self.dt, rtol=1e-6, atol=0.0):
            raise ConfigError("the vehicle's run wrote its ballast forces at other times than "
                              "every [simulation] macro_step %g s" % self.dt)
        self.forces = self.forces[:, self.window]

    @staticmethod
    def _window(xs, length):
        """The sleepers the block carries: all of them, or (track_window)
        those within length / 2 of the track's middle, where the receivers
        stand; at least three."""
        if length is None:
            return list(range(len(xs)))
        mid = 0.5 * (xs[0] + xs[-1])
        out = [i for i, x in enumerate(xs) if abs(x - mid) <= 0.5 * length + 1e-9]
        if len(out) < 3:
            raise ConfigError("[soil] mitigation.track_window %g m holds %d of the track's "
                              "sleepers: it must hold at least three" % (length, len(out)))
        return out

    def _scene(self, soil, name):
        try:
            return two_step.write_scene(
                self.scene, self.scene_dir, soil, os.path.join(self.folder, name + ".toml"),
                "The vehicle's run of a soil study (fe_soil/study_load.py): the scene\n"
                "with [soil] mitigation.duration as its end time, on a lumped soil.",
                self.load["duration"])
        except scene_file.SceneWriteError as e:
            raise ConfigError("the vehicle's run cannot be written: %s" % e)

    def _run(self, soil, name):
        """(sleepers' x, t, forces[time, sleeper]) of the monolithic run."""
        path = self._scene(soil, name)
        out = os.path.join(self.folder, name)
        print("mitigation: the vehicle's run (%s)" % name, flush=True)
        p = subprocess.run([self.master, "run", "--scene", path, "--case", "monolithic",
                            "--out", out], capture_output=True, text=True)
        if p.returncode != 0:
            said = "\n".join((p.stdout + p.stderr).strip().splitlines()[:40])
            raise ConfigError("the vehicle's run (%s run --scene %s --case monolithic: the "
                              "scene with [soil] mitigation.duration = %g s as its "
                              "[simulation] end_time) failed:\n%s"
                              % (self.master, path, self.load["duration"], said))
        head, data = two_step.read_csv(os.path.join(out, "monolithic", "soil_forces.csv"))
        try:
            xs = [float(x) for x in head[1:]]
        except ValueError:
            raise ConfigError("%s: its header does not give the sleepers' positions"
                              % os.path.join(out, "monolithic", "soil_forces.csv"))
        return xs, data[:, 0], data[:, 1:]

    def take_block(self):
        """The block the lumped soil was fitted to, once (None if not kept):
        at rest, its statics to start from zero."""
        soil, self._block = self._block, None
        if soil is not None:
            soil.forget_statics()
        return soil

    def drive(self, soil):
        """(t, v[time, receiver, component]) every macro step: statics under
        the first row, then the rows linear in between."""
        return two_step.one_way(soil, self.forces, self.t, self.dt)

    def text(self):
        v = self.scene.get("vehicle", {})
        return ("the scene's vehicle (%s) at %g km/h on its track, by the two-step method: the "
                "forces into the ballast under each of its %d sleepers (each a footprint, the "
                "receivers beside the middle one) from a monolithic run on a lumped soil fitted "
                "to the static stiffness of the block they were fitted to (k_f = %.4g N/m, "
                "k_c = %.4g N/m), applied one way from the static state, recorded over %g s "
                "every %g s.%s The forces are those of the track on that lumped soil: a "
                "variant's own effect on them is left out, and every band above the highest "
                "judged one is beyond what the mesh resolves (PPV, KB_Fmax and the overall "
                "level are taken below it)" % (
                    v.get("model", "wheel"), v.get("speed_kmh", float("nan")),
                    len(self.footprints), self.kf, self.kc, self.load["duration"], self.dt,
                    "" if len(self.footprints) == self.track else
                    " The block carries %d of the track's %d sleepers, those within %g m of its "
                    "middle ([soil] mitigation.track_window %g m): the others' forces are left "
                    "out." % (len(self.footprints), self.track, 0.5 * self.load["track_window"],
                              self.load["track_window"])))


def make(scene, load, cfg, block, master, out, scene_dir=".", keep=False):
    """The study's load: Ricker or Train (fitted to block(footprints), kept
    for its take_block if `keep`, its runs in out)."""
    if load["load"] == "train":
        return Train(scene, load, cfg, block, master, out, scene_dir, keep)
    return Ricker(scene, load)
