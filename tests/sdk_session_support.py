"""What the Python SDK's session tests share: the example soil served in a
child process over a real socket, and a master's side of the wire (framed
Envelopes, Hello with the answer to a challenge)."""

import os
import runpy
import socket
import struct
import subprocess

from railcosim_sdk.session import Session, auth_answer
from railcosim_sdk.wire import PROTOCOL_VERSION, pb

# The example soil's configuration the session tests serve.
SOIL_TOML = ("[soil]\nmass = 699.6\nstiffness = 121.08e6\ndamping = 341.9e3\n"
             "coupling_stiffness = 43.72e6\ncoupling_damping = 0.0\n")

# The same values as a participant's configuration.
SOIL_CONFIG = {"mass": 699.6, "stiffness": 121.08e6, "damping": 341.9e3,
               "coupling_stiffness": 43.72e6, "coupling_damping": 0.0}


def example_soil(src):
    """The example soil's module namespace (its LumpedSoil participant)."""
    return runpy.run_path(os.path.join(src, "examples", "python_soil", "soil_participant.py"))


class Frames:
    """A channel whose frames are given (received in order); what it is sent
    is kept in `sent`, as Envelopes. `what` names its peer in errors."""

    def __init__(self, envelopes=(), what="the track participant"):
        self.envelopes = list(envelopes)
        self.sent = []
        self.what = what

    def receive(self, timeout=None):
        return self.envelopes.pop(0)

    def send(self, env):
        self.sent.append(env)

    def send_bytes(self, b, timeout=None):
        self.sent.append(pb.Envelope.FromString(b))


def configured_session(soil, n, h):
    """A Session of the example soil (`soil`: example_soil()'s namespace),
    greeted and configured with one ss interface of n points at macro step h."""
    s = Session(soil["LumpedSoil"](), None, "test", SOIL_CONFIG)
    s.handle(pb.Envelope(id=1, hello=pb.Hello(protocol_version=PROTOCOL_VERSION,
                                              participant="soil")))
    c = pb.Configure(participant="soil", macro_step=h, end_time=1.0, micro_steps=10)
    i = c.interfaces.add(cut="ss", peer="track", stiffness=25.5e6, damping=4e4)
    i.x.extend([0.3 + 0.6 * k for k in range(n)])
    i.receives.extend([1, 2])
    i.sends.extend([1, 2])
    s.handle(pb.Envelope(id=2, configure=c))
    return s


def run_window(session, link, master):
    """Runs session's window of two steps on the direct plane, `link` its one
    peer link and `master` the channel its reports go to; returns (the
    plane, the ProtocolError it raised or None)."""
    from railcosim_sdk.direct import Plane
    from railcosim_sdk.wire import ProtocolError
    plane = Plane(session, master, None)
    plane.links, plane.opened, plane.point, plane.refresh = [link], True, 0, False
    plane.timeout, plane.end, plane.why = 1.0, 2, ""
    plane.begin(1)
    try:
        plane.run(0.0, 64)
    except ProtocolError as e:
        return plane, e
    return plane, None


def write_soil_config(work):
    """Writes the example soil's configuration into work; returns its path."""
    path = os.path.join(work, "soil.toml")
    with open(path, "w") as f:
        f.write(SOIL_TOML)
    return path


def serve(src, config, *options):
    """Starts the SDK example soil on config; returns (child, (host, port))."""
    child = subprocess.Popen(
        ["/usr/bin/python3", os.path.join(src, "examples", "python_soil", "soil_participant.py"),
         "--config", config] + list(options),
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    line = child.stdout.readline()
    assert line.startswith("listening on "), line
    host, port = line.split()[-1].rsplit(":", 1)
    return child, (host, int(port))


class Master:
    """The master's side of one session: framed Envelopes over a socket."""

    def __init__(self, address, timeout=10, secret=None):
        self.s = socket.create_connection(address, timeout=timeout)
        self.buf = b""
        self.id = 0
        self.secret = secret

    def send(self, **body):
        self.id += 1
        p = pb.Envelope(id=self.id, **body).SerializeToString()
        self.s.sendall(struct.pack(">I", len(p)) + p)
        return self.receive()

    def receive(self):
        """The next Envelope, or None once the participant has closed."""
        while len(self.buf) < 4 or len(self.buf) < 4 + struct.unpack(">I", self.buf[:4])[0]:
            chunk = self.s.recv(65536)
            if not chunk:
                return None
            self.buf += chunk
        n = struct.unpack(">I", self.buf[:4])[0]
        e = pb.Envelope.FromString(self.buf[4:4 + n])
        self.buf = self.buf[4 + n:]
        return e

    def hello(self, participant="soil", secret=None):
        """Hello as the master; answers a challenge with secret (else the session's)."""
        r = self.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                                     participant=participant))
        if not r.HasField("challenge"):
            return r
        return self.send(auth=pb.Auth(mac=auth_answer(secret or self.secret, participant,
                                                      r.challenge.nonce)))
