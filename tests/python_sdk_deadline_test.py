#!/usr/bin/env python3
"""Write deadlines of the Python SDK, against the SDK example soil in a child
process: a master that stops reading replies, and a peer that stops reading
PeerData, each hold the soil no longer than the deadline (10 s for the
master, the link's timeout for a peer): the session ends with an error that
names who stopped reading (logged; to the master for a peer), and the next
master is served. Usage: python_sdk_deadline_test.py SOURCE_DIR"""

import os
import socket
import struct
import subprocess
import sys
import threading
import time

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk.wire import E, PROTOCOL_VERSION, pb  # noqa: E402

N = 1000  # coupling points of the master's case: a Save's reply is 4 N values (32 kB)
N_PEER = 100  # the peer's case: cheap steps (the soil's dense solve), PeerData of 1.6 kB
failures = []


def check(what, cond, detail=""):
    if not cond:
        failures.append("%s %s" % (what, detail))


class Peer:
    def __init__(self, sock):
        self.s, self.buf, self.id = sock, b"", 0
        self.s.settimeout(30)

    @classmethod
    def connect(cls, address, rcvbuf=None):
        s = socket.socket()
        if rcvbuf:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        s.connect(address)
        return cls(s)

    def post(self, **body):
        self.id += 1
        p = pb.Envelope(id=self.id, **body).SerializeToString()
        self.s.sendall(struct.pack(">I", len(p)) + p)

    def receive(self):
        while len(self.buf) < 4 or len(self.buf) < 4 + struct.unpack(">I", self.buf[:4])[0]:
            chunk = self.s.recv(1 << 20)
            if not chunk:
                return None
            self.buf += chunk
        n = struct.unpack(">I", self.buf[:4])[0]
        e, self.buf = pb.Envelope.FromString(self.buf[4:4 + n]), self.buf[4 + n:]
        return e

    def send(self, **body):
        self.post(**body)
        return self.receive()


def configured(address, rcvbuf=None, n=N):
    m = Peer.connect(address, rcvbuf)
    r = m.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                              participant="soil"))
    assert r.HasField("hello_reply"), r
    c = pb.Configure(participant="soil", macro_step=1e-4, end_time=1.0, micro_steps=10)
    i = c.interfaces.add(cut="ss", peer="track", stiffness=25.5e6, damping=4e4)
    i.x.extend([0.3 + 0.6 * k for k in range(n)])
    i.receives.extend([1, 2])
    i.sends.extend([1, 2])
    r = m.send(configure=c)
    assert r.HasField("configured"), r
    d = pb.CouplingData()
    d.interfaces.add(displacement=[1e-4] * n, velocity=[0.0] * n)
    assert m.send(initialize=pb.Initialize(inputs=d)).HasField("step_report")
    return m


def served_within(address, seconds):
    """Seconds until a new master gets a HelloReply (None: not within `seconds`)."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < seconds:
        try:
            r = Peer.connect(address).send(hello=pb.Hello(
                protocol_version=PROTOCOL_VERSION, role="master", participant="soil"))
            if r is not None and r.HasField("hello_reply"):
                return time.monotonic() - t0
        except OSError:
            pass
        time.sleep(0.25)
    return None


log = open(os.path.join(os.environ.get("TMPDIR", "/tmp"), "sdk_deadline_%d.err" % os.getpid()),
           "w+")
child = subprocess.Popen(["/usr/bin/python3", os.path.join(src, "examples", "python_soil",
                                                            "soil_participant.py"),
                          "--config", os.path.join(src, "scenes", "soil.toml")],
                         stdout=subprocess.PIPE, stderr=log, text=True)
try:
    line = child.stdout.readline()
    assert line.startswith("listening on "), line
    host, port = line.split()[-1].rsplit(":", 1)
    address = (host, int(port))

    # A master that asks and never reads: 400 Saves of 32 kB each (far more
    # than the socket buffers hold).
    m = configured(address, rcvbuf=4096)
    for _ in range(400):
        m.post(save=pb.Save())
    stalled = time.monotonic()
    waited = served_within(address, 25)
    check("the next master is served within 25 s of the master that stopped reading",
          waited is not None, "(still BUSY)")
    log.seek(0)
    text = log.read()
    check("the soil names the master that stopped reading",
          "the master at %s:%d did not read a frame" % m.s.getsockname()[:2] in text, text)
    print("freed after %.1f s" % (time.monotonic() - stalled))
    m.s.close()

    # A peer that stops reading: the soil connects to it on the direct plane;
    # it sends the soil its data for every point and reads nothing of the
    # soil's (16 kB a point).
    server = socket.socket()
    server.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    m = configured(address, n=N_PEER)
    links = pb.Links(session=b"k" * 16, timeout_ms=3000)
    links.links.add(peer="track", host="127.0.0.1", port=server.getsockname()[1],
                    interfaces=[0])
    assert m.send(links=links).HasField("ack")
    m.post(window=pb.Window(first_step=0, end_step=100000))
    conn, _ = server.accept()
    peer = Peer(conn)
    h = peer.receive()
    check("peer hello", h is not None and h.HasField("hello"), str(h))
    peer.post(hello_reply=pb.HelloReply(protocol_version=PROTOCOL_VERSION, participant="track"))

    def feed():
        d = pb.CouplingData()
        d.interfaces.add(displacement=[1e-4] * N_PEER, velocity=[0.0] * N_PEER)
        try:
            for k in range(100000):
                peer.post(peer_data=pb.PeerData(point=k, data=d))
        except OSError:
            pass  # the soil gave up on this link
    threading.Thread(target=feed, daemon=True).start()
    # The soil steps until the socket buffers between it and the peer are
    # full (megabytes: many steps), then waits the link's 3 s for the peer
    # to read.
    t0 = time.monotonic()
    r = m.receive()
    while r is not None and r.HasField("reports"):
        r = m.receive()
    took = time.monotonic() - t0
    check("PEER_FAILED naming the track, which stopped reading", r is not None and
          r.HasField("error") and r.error.code == E.PEER_FAILED and r.error.sender == "track"
          and "the track participant did not read a frame" in r.error.message and
          "within 3 s (it stopped reading)" in r.error.message, str(r))
    check("named within 60 s of the link opening", took < 60, "%.1f s" % took)
    print("the peer named after %.1f s" % took)
    check("the next master is served after the peer",
          served_within(address, 10) is not None, "(still BUSY)")
    conn.close()
    server.close()
finally:
    child.kill()
    child.wait()
    log.close()
    os.unlink(log.name)

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
