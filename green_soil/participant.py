"""The soil from the Green's functions of a layered half-space as a
railcosim participant: the lower side of the ss cut (the ballast), on the
Python SDK.

    /usr/bin/python3 -m green_soil.participant [--output-dir DIR] [SDK options]

Its configuration is the scene's [soil] table with model = "green"
(green_soil/config.py lists the keys); the master starts it itself, as it
starts the FE soil. It serves the ss-xt exchange: it receives the ballast
force per sleeper (positive down, one rail's share; the other rail's
mirror image carries the same force) and sends each footprint's mean
displacement and velocity, by causal convolution with the footprint
responses (green_soil/track.py). History channels: each receiver's
vertical velocity (r8m_vz_mps, ...); results and output files as the FE
soil's (vibration.csv, receivers.csv), with the horizontal velocities (x
along the rail, y away from the track axis) and, in vibration.csv, their
one-third-octave levels after the vertical ones (Lv_x_..., Lv_y_...).
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sdk",
                                "python"))
import railcosim_sdk as rc  # noqa: E402

from fe_soil import measures  # noqa: E402
from fe_soil.config import channel_names  # noqa: E402

from . import config as green_config  # noqa: E402
from . import cost  # noqa: E402
from .outputs import components, vertical_up, vibration_csv  # noqa: E402
from .resolution import receiver_bands  # noqa: E402
from .track import TrackSoil  # noqa: E402

KEEP_SAVES = 8  # states held for restore (implicit coupling restores the latest)


class GreenSoilParticipant(rc.Participant):
    name = "soil"

    def __init__(self, output_dir=None):
        self.output_dir = output_dir
        self.soil = None
        self.saves = {}

    def settings(self, config, interfaces):
        """The checked configuration, footprints and receiver position;
        nothing is computed."""
        try:
            cfg = green_config.parse(config)
        except green_config.ConfigError as e:
            raise rc.BadRequest(str(e))
        if len(interfaces) != 1 or interfaces[0].cut != "ss" or interfaces[0].upper:
            raise rc.BadInterface("the Green's-function soil serves one interface, the lower side "
                                  "of the ss cut (the ballast); got %s"
                                  % ", ".join(map(repr, interfaces)))
        i = interfaces[0]
        if i.receives != ("force",) or i.sends != ("displacement", "velocity"):
            raise rc.BadInterface(
                "interface ss receives %s and sends %s; the Green's-function soil serves the ss-xt "
                "exchange only (it receives the ballast force and sends its displacement and "
                "velocity): use a case with ss-xt (e.g. ss-xt-jacobi)"
                % ("/".join(i.receives) or "nothing", "/".join(i.sends) or "nothing"))
        if len(i.footprints) != i.n or i.n == 0:
            raise rc.BadInterface("interface ss has %d footprints for %d points; this soil needs "
                                  "the master's footprints" % (len(i.footprints), i.n))
        fps = [(f.x, f.y, f.length, f.width) for f in i.footprints]
        xs = [f.x for f in i.footprints]
        rx = 0.5 * (min(xs) + max(xs)) if cfg["receiver_x"] is None else cfg["receiver_x"]
        try:  # what the keys imply together, before anything is allocated
            cost.check(cfg, fps, [(rx, d) for d in cfg["receivers"]], self.run.macro_step,
                       self.run.end_time)
        except green_config.ConfigError as e:
            raise rc.BadRequest(str(e))
        return cfg, fps, rx

    def check(self, config, interfaces):
        self.settings(config, interfaces)

    def configure(self, config, interfaces):
        cfg, fps, rx = self.settings(config, interfaces)
        self.cfg = cfg
        H = self.run.macro_step
        memory = min(cfg["memory"], self.run.end_time + H)
        r_memory = min(cfg["receiver_memory"], self.run.end_time + H)
        start = time.perf_counter()
        try:
            self.soil = TrackSoil(cfg["layers"], fps, [(rx, d) for d in cfg["receivers"]], H,
                                  memory, cfg["f_max"], workers=cfg["workers"], horizontal=True,
                                  receiver_memory=r_memory)
        except ValueError as e:
            raise rc.BadInterface(str(e))
        self.clock = {"build": time.perf_counter() - start, "advance": 0.0, "n": 0}
        self.n = len(fps)
        self.distances = cfg["receivers"]
        self.receiver_x = [rx] * len(self.distances)
        self.history = tuple(channel_names(self.distances))
        self.results_fields = ("soil_m", "receiver_distance_m", "ppv_mps", "kb_fmax_z")
        self.micro_steps = 0
        self.saves = {}
        self.save_count = 0
        self.last = np.zeros(self.n)
        self.series = []  # receivers' velocity after every step (z, then x, then y)
        for name in ("vibration.csv", "receivers.csv"):
            if self.output_dir and os.path.exists(os.path.join(self.output_dir, name)):
                os.remove(os.path.join(self.output_dir, name))

    def statics(self, inputs):
        f = np.array(inputs[0].force.start, dtype=float)
        self.last = self.soil.reset(f)
        self.series = []
        return [{"displacement": self.last, "velocity": np.zeros(self.n)}]

    def advance(self, t, H, inputs):
        w = inputs[0].force
        start = time.perf_counter()
        u, v, r = self.soil.step(np.array(w.start, dtype=float), np.array(w.end, dtype=float))
        self.clock["advance"] += time.perf_counter() - start
        self.clock["n"] += 1
        self.micro_steps += 1
        if not (np.isfinite(u).all() and np.isfinite(v).all()):
            raise rc.StepFailed("the soil's displacements are not finite at t = %g s" % (t + H))
        self.last = u
        self.series.append(r)
        return [{"displacement": u, "velocity": v}]

    def save(self):
        self.save_count += 1
        self.saves[self.save_count] = (self.soil.save(), len(self.series), self.last.copy())
        for old in [k for k in self.saves if k <= self.save_count - KEEP_SAVES]:
            del self.saves[old]
        return [float(self.save_count)]

    def restore(self, state):
        if len(state) != 1 or int(state[0]) not in self.saves:
            raise rc.BadRequest("restore: the soil holds its last %d saved states; this one is "
                                "not among them" % KEEP_SAVES)
        soil_state, n_series, last = self.saves[int(state[0])]
        self.soil.restore(soil_state)
        del self.series[n_series:]
        self.last = last.copy()

    def history_values(self):
        n = len(self.history)
        return [float(x) for x in vertical_up(self.series[-1][:n])] if self.series else [0.0] * n

    def max_abs_displacement(self):
        return float(np.abs(self.last).max()) if len(self.last) else 0.0

    def results(self):
        c = self.clock
        print("green_soil: %d footprints, %d receivers, memory %d steps (receivers %d): built in "
              "%.1f s (cache %s); %d steps %.1f s (%.3f ms each); settled to %.2g of the elastic "
              "static"
              % (self.n, len(self.distances), self.soil.M, self.soil.M_receivers, c["build"],
                 "hit" if self.soil.cache_hit else "miss", c["n"], c["advance"],
                 1e3 * c["advance"] / max(1, c["n"]), self.soil.settled),
              file=sys.stderr, flush=True)
        if not self.series:
            zeros = np.zeros(len(self.distances))
            return (self.last, np.array(self.distances), zeros, zeros)
        dt = self.run.macro_step
        v = components(np.array(self.series), len(self.distances))
        s = [measures.receiver_summary(v[:, k, :], dt) for k in range(v.shape[1])]
        if self.output_dir:
            t = dt * np.arange(1, len(v) + 1)
            os.makedirs(self.output_dir, exist_ok=True)
            write(os.path.join(self.output_dir, "vibration.csv"),
                  vibration_csv(self.history, self.receiver_x, self.distances, s,
                                receiver_bands(self.cfg, dt * len(v), dt)))
            write(os.path.join(self.output_dir, "receivers.csv"),
                  measures.receivers_csv(self.history, t, v))
        return (self.last, np.array(self.distances), np.array([r["ppv"] for r in s]),
                np.array([r["kb_fmax"][2] for r in s]))


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main(argv=None):
    parser = argparse.ArgumentParser(add_help=False)
    parser.add_argument("--output-dir")
    parser.add_argument("--scene-file")  # the master names the scene; unused here
    mine, rest = parser.parse_known_args(argv)
    rc.serve(GreenSoilParticipant(mine.output_dir), rest)


if __name__ == "__main__":
    main()
