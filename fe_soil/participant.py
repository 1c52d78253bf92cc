"""The finite-element soil as a railcosim participant: the lower side of the
ss cut (the ballast), on the Python SDK. Physics only; the SDK speaks the
protocol.

    /usr/bin/python3 -m fe_soil.participant [--output-dir DIR] [SDK options]
    mpirun -n 2 /usr/bin/python3 -m fe_soil.participant ...

Its configuration is the scene's [soil] table with model = "fe" (the master
sends it in Configure.own_config; --config FILE gives one by hand):
fe_soil/config.py lists the keys. The exchange it serves is ss-xt: it
receives the ballast force per sleeper (positive down, one rail's share),
spreads it as a uniform pressure over the point's footprint and sends the
footprint's mean displacement and velocity. ss-xx (the soil receiving the
sleepers' motion, with the ballast spring and damper inside the soil) is
refused. With several MPI ranks, rank 0 serves the protocol and the others
follow every call that touches the mesh (they receive an operation and its
arrays from rank 0 and make the same collective call).

History channels: the vertical velocity of each receiver (r8m_vz_mps, ...).
Results: soil_m (the footprints' displacement, -> soil.csv) and per
receiver its distance, PPV and vertical KB_Fmax. With --output-dir, rank 0
writes there, at the end of a run, vibration.csv (per receiver: PPV, KB_Fmax
per component, vertical one-third-octave levels, the bands resolved there:
fe_soil/resolution.py) and receivers.csv (the velocity series); the master
passes its run folder when it starts the soil.
"""
import argparse
import os
import sys
import time

import numpy as np
from mpi4py import MPI

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sdk",
                                "python"))
import railcosim_sdk as rc  # noqa: E402

from . import config as fe_config  # noqa: E402
from . import measures, resolution  # noqa: E402

OPS = 7  # the message tag of an operation for the followers
KEEP_SAVES = 8  # states held for restore (implicit coupling restores the latest)


class Core:
    """What every rank does: the FESoil and the saved states. Rank 0 calls
    `call(op, ...)`, which sends the operation to the other ranks first."""

    def __init__(self, comm):
        self.comm = comm
        self.soil = None
        self.saves = {}

    def call(self, op, *args):
        for r in range(1, self.comm.size):
            self.comm.send((op, args), dest=r, tag=OPS)
        return getattr(self, op)(*args)

    def build(self, params):
        from .model import FESoil

        self.soil = None
        self.saves = {}
        self.soil = FESoil(params, self.comm)
        return self.soil

    def statics(self, forces):
        # The master's coupled static iteration: its solves may be inexact
        # while the forces still change (FESoil.statics).
        return self.soil.statics(forces, iterating=True)

    def advance(self, t, H, f0, f1):
        return self.soil.advance(t, H, f0, f1)

    def save(self, key):
        self.saves[key] = self.soil.save()
        for old in [k for k in self.saves if k <= key - KEEP_SAVES]:
            del self.saves[old]

    def restore(self, key):
        self.soil.restore(self.saves[key])

    def release(self):
        """Rank 0: ends the other ranks' loops."""
        for r in range(1, self.comm.size):
            self.comm.send(("stop", ()), dest=r, tag=OPS)


def follow(core):
    """The loop of ranks other than 0. Waits with short sleeps rather than in
    a blocking receive: Open MPI's blocking wait spins a core, which the
    other participants of the run need while the soil is idle."""
    comm = core.comm
    while True:
        pause = 0.0
        while not comm.Iprobe(source=0, tag=OPS):
            time.sleep(pause)
            pause = min(2e-3, pause + 5e-5)
        op, args = comm.recv(source=0, tag=OPS)
        if op == "stop":
            return
        try:
            getattr(core, op)(*args)
        except Exception as e:  # rank 0 meets the same error and reports it
            print("fe_soil rank %d: %s: %s: %s" % (comm.rank, op, type(e).__name__, e),
                  file=sys.stderr, flush=True)


class FESoilParticipant(rc.Participant):
    name = "soil"

    def __init__(self, core, output_dir=None, scene_file=None):
        self.core = core
        self.output_dir = output_dir
        self.where = "%s: " % scene_file if scene_file else ""  # in configuration errors
        self.history = ()
        self.results_fields = ()
        self.save_count = 0

    # ---- configure ----------------------------------------------------
    def settings(self, config, interfaces):
        """The checked configuration, the interface and the block it asks
        for (SoilParams, x offset); nothing is built."""
        try:
            cfg = fe_config.parse(config)
        except fe_config.ConfigError as e:
            raise rc.BadRequest(self.where + str(e))
        if len(interfaces) != 1 or interfaces[0].cut != "ss" or interfaces[0].upper:
            raise rc.BadInterface(
                "the FE soil serves one interface, the lower side of the ss cut (the ballast); "
                "got %s" % ", ".join(map(repr, interfaces)))
        i = interfaces[0]
        if i.receives != ("force",) or i.sends != ("displacement", "velocity"):
            raise rc.BadInterface(
                "interface ss receives %s and sends %s; the FE soil serves the ss-xt exchange "
                "only (it receives the ballast force and sends its displacement and velocity): "
                "use a case with ss-xt (e.g. ss-xt-jacobi). Under ss-xx the ballast spring and "
                "damper would sit inside the soil, which this soil does not model"
                % ("/".join(i.receives) or "nothing", "/".join(i.sends) or "nothing"))
        if len(i.footprints) != i.n:
            raise rc.BadInterface(
                "interface ss has %d footprints for %d points; the FE soil needs the master's "
                "footprints (a master that sends Interface.footprints)" % (len(i.footprints), i.n))
        try:
            params, x_offset = fe_config.block_params(cfg, i.footprints)
        except fe_config.ConfigError as e:
            raise rc.BadRequest(self.where + str(e))
        return cfg, i, params, x_offset

    def check(self, config, interfaces):
        self.settings(config, interfaces)

    def configure(self, config, interfaces):
        cfg, i, params, self.x_offset = self.settings(config, interfaces)
        self.n = i.n
        self.distances = cfg["receivers"]
        self.receiver_x = [x + self.x_offset for x, _ in params.receivers]
        self.history = tuple(fe_config.channel_names(self.distances))
        self.results_fields = ("soil_m", "receiver_distance_m", "ppv_mps", "kb_fmax_z")
        start = time.perf_counter()
        self.soil = self.core.call("build", params)
        self.cfg = cfg
        # Where the time goes, printed on stderr at the end of a run.
        self.clock = {"build": time.perf_counter() - start, "statics": 0.0, "advance": 0.0,
                      "n_statics": 0, "n_advance": 0}
        self.micro_steps = 0
        self.save_count = 0
        self.last = np.zeros(self.n)
        self.clear_output()

    def clear_output(self):
        if self.output_dir:
            for name in ("vibration.csv", "receivers.csv"):
                try:
                    os.remove(os.path.join(self.output_dir, name))
                except FileNotFoundError:
                    pass

    # ---- the steps ----------------------------------------------------
    @property
    def static_iterations(self):
        """The soil's CG iterations in static solves so far: the SDK's
        progress frames while a static solve outlasts the reply limit."""
        soil = self.core.soil
        return int(getattr(soil, "static_iterations", 0))

    def statics(self, inputs):
        f = np.array(inputs[0].force.start, dtype=float)
        start = time.perf_counter()
        self.last = self.core.call("statics", f)
        self.clock["statics"] += time.perf_counter() - start
        self.clock["n_statics"] += 1
        return [{"displacement": self.last, "velocity": np.zeros(self.n)}]

    def advance(self, t, H, inputs):
        w = inputs[0].force
        start = time.perf_counter()
        u, v = self.core.call("advance", t, H, np.array(w.start, dtype=float),
                              np.array(w.end, dtype=float))
        self.clock["advance"] += time.perf_counter() - start
        self.clock["n_advance"] += 1
        self.micro_steps += max(1, int(np.ceil(H / self.soil.dt - 1e-9)))
        self.last = u
        if not (np.isfinite(u).all() and np.isfinite(v).all()):
            raise rc.StepFailed("the FE soil's displacements are not finite at t = %g s" % (t + H))
        return [{"displacement": u, "velocity": v}]

    def save(self):
        self.save_count += 1
        self.core.call("save", self.save_count)
        return [float(self.save_count), float(self.soil.t)]

    def restore(self, state):
        if len(state) != 2 or state[0] not in self.core.saves:
            raise rc.BadRequest("restore: the FE soil holds its last %d saved states; this one is "
                                "not among them" % KEEP_SAVES)
        self.core.call("restore", int(state[0]))

    # ---- outputs ------------------------------------------------------
    def history_values(self):
        if not self.soil.history:
            return [0.0] * len(self.history)
        return [float(v) for v in self.soil.history[-1][1][:, 2]]

    def max_abs_displacement(self):
        return float(np.abs(self.last).max()) if len(self.last) else 0.0

    def summaries(self):
        t, v = self.soil.receiver_series()
        dt = float(t[1] - t[0]) if len(t) > 1 else self.run.macro_step
        return t, v, dt, [measures.receiver_summary(v[:, k, :], dt) for k in range(v.shape[1])]

    def report_time(self):
        c = self.clock
        print("fe_soil: %d DOFs on %d rank(s), dt %.4g ms: built in %.1f s; %d static solves "
              "%.1f s (%d CG iterations); %d macro steps %.1f s (%.2f ms each)"
              % (self.soil.global_dofs(), self.core.comm.size, 1e3 * self.soil.dt, c["build"],
                 c["n_statics"], c["statics"], self.static_iterations, c["n_advance"],
                 c["advance"],
                 1e3 * c["advance"] / max(1, c["n_advance"])), file=sys.stderr, flush=True)

    def results(self):
        if self.soil is not None and getattr(self, "clock", None):
            self.report_time()
        if not self.soil.history:  # asked after a run that ended before its first step
            zeros = np.zeros(len(self.distances))
            return (self.last, np.array(self.distances), zeros, zeros)
        t, v, dt, s = self.summaries()
        if self.output_dir and len(t):
            self.write_output(t, v, s)
        return (self.last, np.array(self.distances), np.array([r["ppv"] for r in s]),
                np.array([r["kb_fmax"][2] for r in s]))

    def write_output(self, t, v, s):
        """vibration.csv and receivers.csv in the output folder (rank 0)."""
        os.makedirs(self.output_dir, exist_ok=True)
        record = len(t) * (t[1] - t[0]) if len(t) > 1 else self.run.macro_step
        write(os.path.join(self.output_dir, "vibration.csv"),
              measures.with_resolved(
                  measures.vibration_csv(self.history, self.receiver_x, self.distances, s),
                  resolution.receiver_bands(self.soil, self.cfg, record)))
        write(os.path.join(self.output_dir, "receivers.csv"),
              measures.receivers_csv(self.history, t, v))


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main(argv=None):
    parser = argparse.ArgumentParser(add_help=False)
    parser.add_argument("--output-dir", help="where rank 0 writes vibration.csv and receivers.csv "
                        "at the end of a run")
    parser.add_argument("--scene-file", help="the scene file, named in configuration errors")
    mine, rest = parser.parse_known_args(argv)
    if "--check-configure" in rest or "-h" in rest or "--help" in rest:  # no mesh, no MPI rank
        rc.serve(FESoilParticipant(None, None, mine.scene_file), rest, parents=[parser])
        return
    from . import model  # noqa: F401  (dolfinx loads before the address is printed)

    comm = MPI.COMM_WORLD
    core = Core(comm)
    if comm.rank != 0:
        follow(core)
        return
    try:
        rc.serve(FESoilParticipant(core, mine.output_dir, mine.scene_file), rest)
    finally:
        core.release()


if __name__ == "__main__":
    main()
