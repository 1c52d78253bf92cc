#!/usr/bin/env python3
"""A soil participant for railcosim on the Python SDK: the lumped soil of
docs/model.md (a soil mass under each sleeper on a spring and damper to the
ground, tied to its neighbours), the lower side of the ss cut.

  soil_participant.py --config scenes/soil.toml [--listen 127.0.0.1:0]
                      [--token-file FILE] [--relayed-only]

--config is any TOML file whose [soil] table holds mass, stiffness, damping,
coupling_stiffness and coupling_damping (a scene file will do). It prints
"listening on HOST:PORT", then serves sessions until interrupted. Newmark
(beta = 1/4, gamma = 1/2) with the fixed number of micro steps per macro
step that Configure gives (simulation.micro_steps in the scene).
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "sdk", "python"))
import railcosim_sdk as rc  # noqa: E402

KEYS = ("mass", "stiffness", "damping", "coupling_stiffness", "coupling_damping")


class LumpedSoil(rc.Participant):
    name = "soil"
    history = ("soil_peak_m",)
    results_fields = ("soil_m",)
    takes_waveforms = True  # advance() evaluates at(t) at each micro step and records

    def configure(self, config, interfaces):
        missing = [k for k in KEYS if k not in config]
        if missing:
            raise rc.BadRequest("the [soil] table of --config lacks " + ", ".join(missing))
        if len(interfaces) != 1 or interfaces[0].cut != "ss" or interfaces[0].upper:
            raise rc.BadInterface("this soil serves only the lower side of the ss cut (the "
                                  "ballast), one interface; got %s" % interfaces)
        i = interfaces[0]
        if i.receives not in (("displacement", "velocity"), ("force",)) or \
                i.sends != ("displacement", "velocity"):
            raise rc.BadInterface("interface ss: it receives displacement and velocity, or "
                                  "force, and sends displacement and velocity")
        if self.run.micro_steps <= 0:
            raise rc.BadRequest("this soil integrates with fixed micro steps; set "
                                "simulation.micro_steps in the scene")
        n = self.n = i.n
        m, kf, cf = (float(config[k]) for k in KEYS[:3])
        kc, cc = float(config["coupling_stiffness"]), float(config["coupling_damping"])
        self.receives_force = i.receives == ("force",)
        self.kb, self.cb = i.stiffness, i.damping
        self.M = np.diag(np.full(n, m))
        self.K = np.diag(np.full(n, kf))
        self.C = np.diag(np.full(n, cf))
        for j in range(n - 1):  # the shear ties between neighbours
            for A, c in ((self.K, kc), (self.C, cc)):
                A[j, j] += c
                A[j + 1, j + 1] += c
                A[j, j + 1] -= c
                A[j + 1, j] -= c
        if not self.receives_force:  # the ballast spring and damper to the held sleepers
            self.K += np.diag(np.full(n, self.kb))
            self.C += np.diag(np.full(n, self.cb))
        self.m = self.run.micro_steps
        h = self.h = self.run.macro_step / self.m
        self.c0 = 1.0 / (0.25 * h * h)
        self.c1 = 0.5 / (0.25 * h)
        self.Keff_inv = np.linalg.inv(self.K + self.c1 * self.C + self.c0 * self.M)
        self.M_inv = np.linalg.inv(self.M)
        self.u = self.v = self.a = np.zeros(n)
        self.micro_steps = 0

    def load(self, inputs, end=False, t=None):
        """The load on the soil masses from the interface's inputs (at t:
        substep waveforms, evaluated there)."""
        i = inputs[0]
        if t is not None:
            if self.receives_force:
                return i.force.at(t)
            return self.kb * i.displacement.at(t) + self.cb * i.velocity.at(t)
        if self.receives_force:
            return (i.force.end if end else i.force.start).copy()
        if end:
            return self.kb * i.displacement.end + self.cb * i.velocity.end
        return self.kb * i.displacement.start + self.cb * i.velocity.start

    def outputs(self, inputs=None):
        self.peak = float(np.abs(self.u).max())  # for the history and the divergence check
        return [{"displacement": self.u, "velocity": self.v}]

    def max_abs_displacement(self):
        return self.peak

    def statics(self, inputs):
        load = self.load(inputs)
        self.u = np.linalg.solve(self.K, load)
        self.v = np.zeros(self.n)
        self.a = self.M_inv @ (load - self.K @ self.u - self.C @ self.v)
        # Micro steps solve for u - origin: the acceleration c0 (u+ - pred)
        # then does not divide the rounding of u itself by beta h^2.
        self.origin, self.origin_load = self.u, -(self.K @ self.u)
        return self.outputs()

    def advance(self, t, H, inputs):
        load = self.load(inputs)
        rate = np.zeros(self.n)
        w = inputs[0].force if self.receives_force else inputs[0].displacement
        sampled = isinstance(w, rc.Sampled)
        if not w.held and not sampled:
            rate = (self.load(inputs, end=True) - load) / H
        if not self.run.carry_acceleration:  # restart consistent with the new inputs
            self.a = self.M_inv @ (load - self.K @ self.u - self.C @ self.v)
        h, t1 = self.h, t + H
        for k in range(1, self.m + 1):
            pu = (self.u - self.origin) + h * self.v + (h * h * 0.25) * self.a
            pv = self.v + (h * 0.5) * self.a
            tk = t1 if k == self.m else t + (t1 - t) * k / self.m  # the micro step's end
            if sampled:
                rhs = self.load(inputs, t=tk) + self.origin_load
            else:
                rhs = (load + (tk - t) * rate) + self.origin_load
            rhs += self.M @ (self.c0 * pu) + self.C @ (self.c1 * pu - pv)
            x = self.Keff_inv @ rhs
            self.a = self.c0 * (x - pu)
            self.v = pv + (0.5 * h) * self.a
            self.u = x + self.origin
            self.micro_steps += 1
            if self.recording:
                self.record(tk, [{"displacement": self.u, "velocity": self.v}])
        return self.outputs()

    def save(self):
        return np.concatenate((self.u, self.v, self.a, self.origin))

    def restore(self, state):
        n = self.n
        if len(state) != 4 * n:
            raise rc.BadRequest("restore: %d values, expected %d" % (len(state), 4 * n))
        self.u, self.v, self.a = state[:n].copy(), state[n:2 * n].copy(), state[2 * n:3 * n].copy()
        self.origin, self.origin_load = state[3 * n:].copy(), -(self.K @ state[3 * n:])

    def history_values(self):
        return (self.peak,)

    def results(self):
        return (self.u,)


if __name__ == "__main__":
    rc.serve(LumpedSoil())
