#!/usr/bin/env python3
"""The Python SDK and the shared secret, as a user and an attacker meet it,
with the SDK example soil in a child process: token files that others may
read, endless (/dev/zero), huge or FIFOs are refused at start-up, naming the
file; with a secret, a hello for another role or from a peer gets nothing but
the challenge (the participant names no role before the answer); after a
right answer the soil proves it holds the secret (HelloReply.proof over both
nonces); a master with a secret refuses a soil without one, naming its
address. Usage: python_sdk_auth_test.py SOURCE_DIR BIN_DIR"""

import os
import socket
import struct
import subprocess
import sys
import tempfile

src, bin_dir = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk.auth import auth_answer, auth_proof  # noqa: E402
from railcosim_sdk.wire import E, PROTOCOL_VERSION, pb  # noqa: E402

SOIL = os.path.join(src, "examples", "python_soil", "soil_participant.py")
SCENE = os.path.join(src, "scenes", "soil.toml")
SECRET = "the soil's shared secret, long enough"
failures = []
work = tempfile.mkdtemp()


def check(what, cond, detail=""):
    if not cond:
        failures.append("%s %s" % (what, detail))


def secret_file(name, mode, text=SECRET):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text + "\n")
    os.chmod(path, mode)
    return path


def start(*args):
    child = subprocess.Popen(["/usr/bin/python3", SOIL, "--config", SCENE] + list(args),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = child.stdout.readline()
    if not line.startswith("listening on "):
        child.kill()
        raise SystemExit("the soil did not start: %s %s" % (line, child.stderr.read()))
    host, port = line.split()[-1].rsplit(":", 1)
    return child, (host, int(port))


# Token files: each refused at start-up, within 10 s, naming the file.
fifo = os.path.join(work, "fifo")
os.mkfifo(fifo, 0o600)
huge = secret_file("huge", 0o600)
os.truncate(huge, 300 << 20)  # sparse: 300 MiB that take no disk
for path, expected in [(secret_file("world", 0o644), "has mode 0644"),
                       (secret_file("everyone", 0o666), "has mode 0666"),
                       (secret_file("group", 0o640), "has mode 0640"),
                       ("/dev/zero", "is not a regular file"), (fifo, "is not a regular file"),
                       (huge, "holds 314572800 bytes; a secret is at most 4096"),
                       (secret_file("short", 0o600, "short"), "at least 16 characters")]:
    try:
        p = subprocess.run(["/usr/bin/python3", SOIL, "--config", SCENE, "--token-file", path],
                           capture_output=True, text=True, timeout=10)
        check("token file %s refused" % path, p.returncode != 0 and
              ("the token file %s " % path) in p.stderr and expected in p.stderr,
              p.stdout + p.stderr)
    except subprocess.TimeoutExpired:
        check("token file %s refused within 10 s" % path, False)


class Master:
    def __init__(self, address=None, sock=None):
        self.s = sock or socket.create_connection(address, timeout=5)
        self.s.settimeout(10)
        self.buf = b""

    def post(self, **body):
        p = pb.Envelope(id=1, **body).SerializeToString()
        self.s.sendall(struct.pack(">I", len(p)) + p)

    def send(self, **body):
        self.post(**body)
        return self.receive()

    def receive(self):
        while len(self.buf) < 4 or len(self.buf) < 4 + struct.unpack(">I", self.buf[:4])[0]:
            chunk = self.s.recv(65536)
            if not chunk:
                return None, b""
            self.buf += chunk
        n = struct.unpack(">I", self.buf[:4])[0]
        raw, self.buf = self.buf[4:4 + n], self.buf[4 + n:]
        return pb.Envelope.FromString(raw), raw


child, address = start("--token-file", secret_file("token", 0o600))
try:
    # No role named before the answer: a hello for the track, and a peer's
    # hello, get the challenge alone.
    for hello in (pb.Hello(protocol_version=PROTOCOL_VERSION, role="master", participant="track"),
                  pb.Hello(protocol_version=PROTOCOL_VERSION, role="peer", participant="track",
                           peer_of="vehicle", session=bytes(16))):
        r, raw = Master(address).send(hello=hello)
        check("challenge first for %s/%s" % (hello.role, hello.participant),
              r is not None and r.WhichOneof("body") == "challenge" and b"soil" not in raw,
              str(r))
    # Mutual: the master's nonce in the hello, the soil's proof after a right answer.
    mine = os.urandom(32)
    m = Master(address)
    c, _ = m.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                                 participant="soil", nonce=mine))
    r, _ = m.send(auth=pb.Auth(mac=auth_answer(SECRET, "soil", c.challenge.nonce)))
    check("the soil proves the secret", r is not None and r.HasField("hello_reply") and
          r.hello_reply.proof == auth_proof(SECRET, "soil", mine, c.challenge.nonce), str(r))
    m.send(shutdown=pb.Shutdown())

    # As the connecting end of a peer link, the soil refuses a "track" that
    # challenges it but cannot prove the secret (an impostor at the address).
    m = Master(address)
    c, _ = m.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                                 participant="soil"))
    m.send(auth=pb.Auth(mac=auth_answer(SECRET, "soil", c.challenge.nonce)))
    conf = pb.Configure(participant="soil", macro_step=1e-4, end_time=1e-3, micro_steps=10)
    conf.interfaces.add(cut="ss", peer="track", stiffness=25.5e6, damping=4e4, x=[0.3, 0.9],
                        receives=[1, 2], sends=[1, 2])
    m.send(configure=conf)
    d = pb.CouplingData()
    d.interfaces.add(displacement=[0.0] * 2, velocity=[0.0] * 2)
    m.send(initialize=pb.Initialize(inputs=d))
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    links = pb.Links(session=b"k" * 16, timeout_ms=5000)
    links.links.add(peer="track", host="127.0.0.1", port=server.getsockname()[1], interfaces=[0])
    m.send(links=links)
    m.post(window=pb.Window(first_step=0, end_step=1))
    conn, _ = server.accept()
    impostor = Master(sock=conn)
    h, _ = impostor.receive()
    check("the soil's peer hello carries its nonce", h is not None and len(h.hello.nonce) == 32,
          str(h))
    impostor.send(challenge=pb.Challenge(nonce=bytes(32)))  # the soil's Auth comes back
    impostor.post(hello_reply=pb.HelloReply(protocol_version=PROTOCOL_VERSION,
                                            participant="track"))
    r, _ = m.receive()
    while r is not None and r.HasField("reports"):
        r, _ = m.receive()
    check("an impostor peer is refused", r is not None and r.HasField("error") and
          r.error.code == E.UNAUTHORIZED and r.error.message.startswith(
              "peer link to the track participant at 127.0.0.1:%d: it did not prove that it "
              "holds the shared secret of --token-file (its proof was missing)"
              % server.getsockname()[1]), str(r))
    conn.close()
    server.close()
finally:
    child.kill()
    child.wait()

# A master with a secret refuses a soil without one, naming it and its address.
child, address = start()
try:
    p = subprocess.run([os.path.join(bin_dir, "master"), "run", "--scene", SCENE, "--case",
                        "ss-xx-jacobi", "--node", "soil=%s:%d" % address, "--token-file",
                        os.path.join(work, "token"), "--out", os.path.join(work, "out")],
                       capture_output=True, text=True, timeout=60)
    check("a soil without the secret is refused", p.returncode != 0 and
          ("soil node at %s:%d: it asked no challenge, so it cannot prove that it holds the "
           "shared secret of --token-file" % address) in p.stdout + p.stderr,
          p.stdout + p.stderr)
finally:
    child.kill()
    child.wait()

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
