#!/usr/bin/env python3
"""A soil participant for railcosim, outside the product: the lumped soil of
the shared model, served over the co-simulation protocol (version 2).

Everything about the coupling comes from the interface the master describes
at configure time: the cut (it serves the lower side of "ss", the ballast),
the coupling points, what it receives (displacement and velocity, or force)
and the ballast's stiffness and damping. The soil's own parameters come from
this program's input: the [soil] table of a scene file. Nothing here reads
the product's model section of Configure.

  soil_participant.py --scene scenes/soil.toml [--listen 127.0.0.1:0]
                      [--token-file FILE] [--proto protocol/railcosim.proto]

It prints "listening on HOST:PORT" first, then serves sessions one after
another until interrupted. Time integration: Newmark, beta = 1/4, gamma = 1/2,
with the fixed number of micro steps per macro step that Configure gives
(simulation.micro_steps in the scene); at every communication point it
restarts from an acceleration consistent with the new inputs.
"""

import argparse
import hashlib
import hmac
import importlib
import os
import secrets
import socket
import struct
import subprocess
import sys
import tempfile
import tomllib

import numpy as np

PROTOCOL_VERSION = 2
MAX_FRAME = 8 << 20


def load_messages(proto_path):
    """Compiles the protocol's schema with protoc and imports the result."""
    out = tempfile.mkdtemp(prefix="railcosim_proto_")
    folder, name = os.path.split(os.path.abspath(proto_path))
    subprocess.run(["protoc", "-I", folder, "--python_out", out, name], check=True)
    sys.path.insert(0, out)
    return importlib.import_module(name.replace(".proto", "_pb2"))


class SessionError(Exception):
    """Ends the session with an error reply of the given code."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


class LumpedSoil:
    """Soil masses on springs and dampers to the ground, tied to their
    neighbours, loaded through the ballast (the lower side of the ss cut)."""

    def __init__(self, soil, interface, macro_step, micro_steps):
        n = len(interface.x)
        self.n = n
        self.receives_force = list(interface.receives) == [3]  # FORCE
        kb, cb = interface.stiffness, interface.damping
        m, kf, cf = soil["mass"], soil["stiffness"], soil["damping"]
        kc, cc = soil["coupling_stiffness"], soil["coupling_damping"]
        self.M = np.diag(np.full(n, m))
        self.K = np.diag(np.full(n, kf))
        self.C = np.diag(np.full(n, cf))
        for i in range(n - 1):
            for A, c in ((self.K, kc), (self.C, cc)):
                A[i, i] += c
                A[i + 1, i + 1] += c
                A[i, i + 1] -= c
                A[i + 1, i] -= c
        if not self.receives_force:  # the ballast spring to held sleeper values
            self.K += np.diag(np.full(n, kb))
            self.C += np.diag(np.full(n, cb))
        self.kb, self.cb = kb, cb
        self.H = macro_step
        self.m = micro_steps
        h = macro_step / micro_steps
        self.h = h
        self.c0 = 1.0 / (0.25 * h * h)
        self.c1 = 0.5 / (0.25 * h)
        self.Keff_inv = np.linalg.inv(self.K + self.c1 * self.C + self.c0 * self.M)
        self.M_inv = np.linalg.inv(self.M)
        self.u = np.zeros(n)
        self.v = np.zeros(n)
        self.a = np.zeros(n)
        self.load = np.zeros(n)
        self.rate = np.zeros(n)  # d(load)/dt over the macro step when inputs ramp
        self.held = (np.zeros(n), np.zeros(n), np.zeros(n))
        self.micro_steps = 0

    def hold(self, data, end=None):
        """Applies the inputs held over a macro step (or a static solve); with
        `end`, the inputs ramp linearly from `data` to `end` over the step."""
        self.rate = np.zeros(self.n)
        if end is not None:
            self.hold(end)
            last = self.load
            self.hold(data)
            self.rate = (last - self.load) / self.H
            return
        d, v, f = (np.array(data.displacement), np.array(data.velocity), np.array(data.force))
        want = (0, 0, self.n) if self.receives_force else (self.n, self.n, 0)
        if (len(d), len(v), len(f)) != want:
            raise SessionError(8, "ss inputs: expected %d displacement, %d velocity and %d force "
                               "values, got %d, %d, %d" % (want + (len(d), len(v), len(f))))
        if not (np.all(np.isfinite(d)) and np.all(np.isfinite(v)) and np.all(np.isfinite(f))):
            raise SessionError(8, "ss inputs: a value is not finite")
        self.held = (d, v, f)
        self.load = f.copy() if self.receives_force else self.kb * d + self.cb * v

    def statics(self):
        self.u = np.linalg.solve(self.K, self.load)
        self.v = np.zeros(self.n)
        self.restart()

    def restart(self):
        self.a = self.M_inv @ (self.load - self.C @ self.v - self.K @ self.u)

    def step(self):
        h = self.h
        for k in range(self.m):
            pu = self.u + h * self.v + (h * h * 0.25) * self.a
            pv = self.v + (h * 0.5) * self.a
            load = self.load + self.rate * ((k + 1) * h)  # at the end of the micro step
            rhs = load + self.M @ (self.c0 * pu) + self.C @ (self.c1 * pu - pv)
            u = self.Keff_inv @ rhs
            a = self.c0 * (u - pu)
            self.v = pv + (0.5 * h) * a
            self.u, self.a = u, a
            self.micro_steps += 1

    def outputs(self, pb):
        out = pb.CouplingData()
        i = out.interfaces.add()
        i.displacement.extend(self.u.tolist())
        i.velocity.extend(self.v.tolist())
        return out

    def report(self, pb, step):
        r = pb.StepReport(step=step, t=step * self.H)
        r.outputs.CopyFrom(self.outputs(pb))
        r.max_abs_displacement = float(np.max(np.abs(self.u)))
        r.finite = bool(np.all(np.isfinite(self.u)) and np.all(np.isfinite(self.v)))
        r.history.append(float(np.max(np.abs(self.u))))  # soil_peak_m
        return r

    def save(self, step):
        d, v, f = self.held
        return [float(step), float(self.micro_steps)] + [float(x) for x in np.concatenate(
            (self.u, self.v, self.a, self.load, self.rate, d, v, f))]

    def restore(self, values):
        n = self.n
        nd = 0 if self.receives_force else n
        if len(values) != 2 + 5 * n + 2 * nd + (n - nd):
            raise SessionError(8, "restore: the state does not fit this participant")
        if not all(np.isfinite(values[:2])) or not 0 <= values[0] < 2**53 \
                or not 0 <= values[1] < 2**53:
            raise SessionError(8, "restore: the state does not fit this participant")
        step, self.micro_steps = int(values[0]), int(values[1])
        x = np.array(values[2:])
        self.u, self.v, self.a, self.load = x[:n], x[n:2 * n], x[2 * n:3 * n], x[3 * n:4 * n]
        self.rate = x[4 * n:5 * n]
        rest = x[5 * n:]
        self.held = (rest[:nd], rest[nd:2 * nd], rest[2 * nd:])
        return step


class Session:
    def __init__(self, pb, soil, token):
        self.pb, self.soil_params, self.token = pb, soil, token
        self.state = "hello"
        self.nonce = b""
        self.participant = ""
        self.model = None
        self.carry = False
        self.step = 0

    def reply(self, req):
        """Returns (reply envelope, close after sending)."""
        pb = self.pb
        out = pb.Envelope(id=req.id)
        kind = req.WhichOneof("body")
        if kind == "shutdown" and self.state != "auth":
            out.ack.SetInParent()
            return out, True
        if self.state == "hello":
            if kind != "hello":
                raise SessionError(7, "expected hello, got " + str(kind))
            if req.hello.protocol_version != PROTOCOL_VERSION:
                raise SessionError(3, "this participant speaks protocol version %d" %
                                   PROTOCOL_VERSION)
            if req.hello.participant != "soil":
                raise SessionError(4, "this participant serves the soil participant, not the %s "
                                   "participant" % (req.hello.participant or "unnamed"))
            self.participant = req.hello.participant
            if self.token is not None:
                self.nonce = secrets.token_bytes(32)
                self.state = "auth"
                out.challenge.nonce = self.nonce
                return out, False
            self.state = "configure"
            return self.hello_reply(out), False
        if self.state == "auth":
            message = b"railcosim-auth-v2" + self.participant.encode() + b"\0" + self.nonce
            expected = hmac.new(self.token.encode(), message, hashlib.sha256).digest()
            self.nonce = b""
            if kind != "auth" or not hmac.compare_digest(req.auth.mac, expected):
                raise SessionError(12, "this participant requires the shared secret")
            self.state = "configure"
            return self.hello_reply(out), False
        if self.state == "configure":
            if kind != "configure":
                raise SessionError(7, "expected configure, got " + str(kind))
            self.configure(req.configure)
            self.state = "ready"
            out.configured.history.append("soil_peak_m")
            out.configured.results.append("soil_m")
            return out, False
        return self.dispatch(req, kind, out)

    def hello_reply(self, out):
        out.hello_reply.protocol_version = PROTOCOL_VERSION
        out.hello_reply.participant = "soil"
        out.hello_reply.name = "python soil participant"
        return out

    def configure(self, c):
        if len(c.interfaces) != 1 or c.interfaces[0].cut != "ss" or c.interfaces[0].upper:
            raise SessionError(14, "participant soil: this participant serves only the lower side "
                               "of the ss cut (the ballast), one interface")
        i = c.interfaces[0]
        if list(i.receives) not in ([1, 2], [3]) or list(i.sends) != [1, 2]:
            raise SessionError(14, "participant soil: interface ss: it receives displacement and "
                               "velocity, or force, and sends displacement and velocity")
        if c.micro_steps <= 0:
            raise SessionError(8, "configure: this participant integrates with fixed micro steps; "
                               "set simulation.micro_steps in the scene")
        self.model = LumpedSoil(self.soil_params, i, c.macro_step, c.micro_steps)
        self.carry = c.carry_acceleration

    def dispatch(self, req, kind, out):
        pb, m = self.pb, self.model
        if kind == "statics":
            m.hold(req.statics.inputs.interfaces[0])
            m.statics()
            out.outputs.data.CopyFrom(m.outputs(pb))
            return out, False
        if kind == "initialize":
            m.hold(req.initialize.inputs.interfaces[0])
            m.statics()
            self.step = 0
            out.step_report.CopyFrom(m.report(pb, 0))
            return out, False
        if kind == "set_inputs" or (kind == "step" and req.step.HasField("inputs")):
            msg = req.set_inputs if kind == "set_inputs" else req.step
            if msg.step != self.step:
                raise SessionError(7, "inputs for step %d, the participant is at step %d" %
                                   (msg.step, self.step))
            m.hold(msg.inputs.interfaces[0],
                   msg.inputs_end.interfaces[0] if msg.HasField("inputs_end") else None)
            if not self.carry:  # else keep the integrator's acceleration
                m.restart()
            if kind == "set_inputs":
                out.ack.SetInParent()
                return out, False
        if kind == "step":
            if req.step.step != self.step:
                raise SessionError(7, "step %d asked, the participant is at step %d" %
                                   (req.step.step, self.step))
            m.step()
            self.step += 1
            out.step_report.CopyFrom(m.report(pb, self.step))
            return out, False
        if kind == "get_outputs":
            out.outputs.step = self.step
            out.outputs.t = self.step * m.H
            out.outputs.data.CopyFrom(m.outputs(pb))
            return out, False
        if kind == "get_results":
            out.results.fields.add().values.extend(m.u.tolist())
            out.results.micro_steps = m.micro_steps
            return out, False
        if kind == "save":
            out.state.values.extend(m.save(self.step))
            return out, False
        if kind == "restore":
            self.step = m.restore(list(req.restore.state.values))
            out.ack.SetInParent()
            return out, False
        raise SessionError(8, "this participant does not accept %s messages" % kind)


def read_exactly(conn, n):
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return data


def send(conn, envelope):
    payload = envelope.SerializeToString()
    conn.sendall(struct.pack(">I", len(payload)) + payload)


def serve(conn, pb, soil, token):
    session = Session(pb, soil, token)
    while True:
        header = read_exactly(conn, 4)
        if header is None:
            return
        (length,) = struct.unpack(">I", header)
        if length > MAX_FRAME:
            send(conn, pb.Envelope(error=pb.Error(code=2, message="frame too large", step=-1)))
            return
        payload = read_exactly(conn, length)
        if payload is None:
            return
        req = pb.Envelope()
        try:
            req.ParseFromString(payload)
            reply, close = session.reply(req)
        except SessionError as e:
            reply, close = pb.Envelope(id=req.id, error=pb.Error(
                code=e.code, message=str(e), step=session.step, t=0.0)), True
        except Exception as e:  # a bug here must not take the server down
            reply, close = pb.Envelope(id=req.id, error=pb.Error(
                code=10, message="internal error: %s" % e, step=session.step)), True
        send(conn, reply)
        if close:
            return


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", required=True, help="scene file whose [soil] table holds the soil")
    p.add_argument("--listen", default="127.0.0.1:0", help="HOST:PORT (port 0: any)")
    p.add_argument("--token-file", help="shared secret, as the master's --token-file")
    p.add_argument("--proto", default=os.path.join(here, "..", "..", "protocol",
                                                   "railcosim.proto"))
    args = p.parse_args()
    with open(args.scene, "rb") as f:
        table = tomllib.load(f).get("soil", {})
    keys = ["mass", "stiffness", "damping", "coupling_stiffness", "coupling_damping"]
    missing = [k for k in keys if k not in table]
    if missing:
        sys.exit("%s: [soil] lacks %s" % (args.scene, ", ".join(missing)))
    soil = {k: float(table[k]) for k in keys}
    token = open(args.token_file).read().strip() if args.token_file else None
    pb = load_messages(args.proto)
    host, port = args.listen.rsplit(":", 1)
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    server.bind((host, int(port)))
    server.listen(4)
    print("listening on %s:%d" % server.getsockname(), flush=True)
    try:
        while True:
            conn, _ = server.accept()
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            with conn:
                serve(conn, pb, soil, token)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
