#!/usr/bin/env python3
"""The Python SDK's waveforms, and its session rules against the SDK example
soil served in a child process: the HMAC test vector of docs/protocol.md, the challenge
(wrong and right answers), BUSY for a second master, WRONG_ROLE, and the
errors a bad Configure, bad inputs, a bad step and a bad Restore get, each
with its exact message; on the direct plane, BUSY for a connection that is
not the awaited peer, and a master that leaves while the soil waits for its
peer frees it for the next session; as the connecting end of a peer link,
the hello, the shared secret, PeerData at points 0 and 1, the reports and
WindowDone. Usage: python_sdk_test.py SOURCE_DIR"""

import os
import socket
import struct
import sys
import tempfile
import time

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk.auth import auth_proof  # noqa: E402
from railcosim_sdk.session import auth_answer  # noqa: E402
from railcosim_sdk.wire import E, PROTOCOL_VERSION, pb  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sdk_session_support import Master as SessionMaster, serve, write_soil_config  # noqa: E402

failures = []


def check(what, cond, detail=""):
    if not cond:
        failures.append("%s %s" % (what, detail))


vector = auth_answer("correct horse battery staple", "soil", bytes(range(32))).hex()
check("HMAC test vector", vector ==
      "4e2d5487f0cf7d11491de7fa96b114c303c3bc603281743421002ef021887e49", vector)

# Waveforms: held inputs stay, ramped ones are linear over the step.
import numpy as np  # noqa: E402
from railcosim_sdk import Waveform  # noqa: E402
held = Waveform(np.array([1.0, -2.0]), None, 0.3, 0.1)
check("held waveform", held.held and held.at(0.37) is held.start and held.end is held.start
      and not held.rate().any())
ramp = Waveform(np.array([1.0, -2.0]), np.array([3.0, 2.0]), 0.25, 0.5)
check("ramped waveform", not ramp.held and list(ramp.at(0.25)) == [1.0, -2.0] and
      list(ramp.at(0.5)) == [2.0, 0.0] and list(ramp.at(0.75)) == [3.0, 2.0] and
      list(ramp.rate()) == [4.0, 8.0], str((ramp.at(0.5), ramp.rate())))

# The interface geometry: footprints at the ss cut as the wire carries them,
# and the scene's own table (Configure.own_config) as the configuration of a
# participant served without --config.
from railcosim_sdk import Participant  # noqa: E402
from railcosim_sdk.session import Session  # noqa: E402


class Recorder(Participant):
    name = "soil"

    def configure(self, config, interfaces):
        self.config, self.interfaces = config, interfaces


def configure_recorder(own_config, config=None):
    p = Recorder()
    s = Session(p, None, "test", config)
    s.handle(pb.Envelope(id=1, hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                                               participant="soil")))
    c = pb.Configure(participant="soil", macro_step=1e-4, end_time=1e-3, micro_steps=1,
                     own_config=own_config)
    i = c.interfaces.add(cut="ss", peer="track", x=[0.3, 0.9])
    for x in (0.3, 0.9):
        i.footprints.add(x=x, y=0.65, z=0.0, length=0.6, width=1.3)
    return p, s.handle(pb.Envelope(id=2, configure=c))


rec, reply = configure_recorder('model = "fe"\nf_max = 20.0\n[[layers]]\nthickness = 2.0\n')
fps = rec.interfaces[0].footprints
check("footprints", len(fps) == 2 and [f.x for f in fps] == [0.3, 0.9] and
      all(f.y == 0.65 and f.z == 0.0 and f.length == 0.6 and f.width == 1.3 and
          f.area == 0.6 * 1.3 for f in fps), str(fps))
check("own_config as the configuration", rec.config == {
    "model": "fe", "f_max": 20.0, "layers": [{"thickness": 2.0}]}, str(rec.config))
rec, _ = configure_recorder('model = "fe"\n', {"from": "--config"})
check("--config wins over own_config", rec.config == {"from": "--config"}, str(rec.config))
rec, reply = configure_recorder("")
check("no own_config: an empty configuration", rec.config == {}, str(rec.config))
from railcosim_sdk import Interface  # noqa: E402
check("no footprints at other cuts", Interface(pb.Interface(cut="wr", x=[1.0])).footprints == ())
try:
    configure_recorder("model = = 1")
    check("own_config that is not TOML is refused", False)
except Exception as e:
    check("own_config that is not TOML is refused",
          getattr(e, "code", None) == E.BAD_REQUEST and "own_config is not TOML" in str(e), str(e))

work = tempfile.mkdtemp()
SECRET = "s3cret of the test run"
with open(os.open(os.path.join(work, "token"), os.O_WRONLY | os.O_CREAT, 0o600), "w") as f:
    f.write("  %s\n" % SECRET)
child, address = serve(src, write_soil_config(work), "--token-file", os.path.join(work, "token"))
try:
    def Master():
        return SessionMaster(address, timeout=5, secret=SECRET)

    def error(r, code, message, conn=None):
        if conn is not None:  # the session ends: wait until it is closed
            check("closed after the error", conn.receive() is None)
        check("error %s" % E.Code.Name(code), r is not None and r.HasField("error")
              and r.error.code == code and r.error.message == message, str(r))

    m = Master()
    error(m.hello(secret="wrong"), E.UNAUTHORIZED, "this participant requires the shared secret "
          "of its --token-file; the answer to its challenge was missing or wrong", m)
    m = Master()
    error(m.hello("track"), E.WRONG_ROLE,
          "this program serves the soil participant, not the track participant", m)

    def configured(micro_steps=10, n=4):
        m = Master()
        r = m.hello()
        check("hello reply", r.HasField("hello_reply") and list(r.hello_reply.capabilities)
              == ["direct", "lockstep"], str(r))
        c = pb.Configure(participant="soil", macro_step=1e-4, end_time=1e-3,
                         micro_steps=micro_steps)
        i = c.interfaces.add(cut="ss", peer="track", stiffness=25.5e6, damping=4e4)
        i.x.extend([0.3 + 0.6 * k for k in range(n)])
        i.receives.extend([1, 2])
        i.sends.extend([1, 2])
        return m, m.send(configure=c)

    m, r = configured()
    check("configured", list(r.configured.history) == ["soil_peak_m"] and
          list(r.configured.results) == ["soil_m"], str(r))
    busy = Master()  # a second master while the first one's session runs
    error(busy.receive(), E.BUSY, "this participant already serves a session (from %s:%d)"
          % m.s.getsockname()[:2])

    def data(n, d=1e-4, v=0.0):
        c = pb.CouplingData()
        c.interfaces.add(displacement=[d] * n, velocity=[v] * n)
        return c
    r = m.send(initialize=pb.Initialize(inputs=data(4)))
    check("initialize", r.HasField("step_report") and r.step_report.finite and
          len(r.step_report.outputs.interfaces[0].displacement) == 4, str(r))
    state = m.send(save=pb.Save()).state
    r1 = m.send(step=pb.Step(step=0, h=1e-4, inputs=data(4, 2e-4, 1e-3))).step_report
    check("restore", m.send(restore=pb.Restore(state=state)).HasField("ack"))
    r2 = m.send(step=pb.Step(step=0, h=1e-4, inputs=data(4, 2e-4, 1e-3))).step_report
    check("a step after restore is bitwise the same", r1.SerializeToString() ==
          r2.SerializeToString())
    error(m.send(step=pb.Step(step=3, h=1e-4)), E.OUT_OF_ORDER,
          "a step for macro step 3; the participant is at macro step 1", m)

    m, _ = configured()
    error(m.send(configure=pb.Configure(participant="soil", macro_step=1e-4)), E.OUT_OF_ORDER,
          "configure is allowed once, at the start of a session", m)
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    error(m.send(step=pb.Step(step=0, h=1e-4, inputs=data(3))), E.BAD_REQUEST,
          "interface ss: 3 displacement values, expected 4 (one per coupling point)", m)
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    error(m.send(step=pb.Step(step=0, h=1e-4, inputs=data(4, float("nan")))), E.BAD_REQUEST,
          "interface ss: a displacement value is not finite", m)
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    error(m.send(restore=pb.Restore(state=pb.State(values=[1.0, 2.0]))), E.BAD_REQUEST,
          "restore: the state does not fit this participant (it was not saved by it in this "
          "session)", m)
    # Recording off is acknowledged (substep waveforms themselves:
    # python_waveform_test.py).
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    check("recording off is acknowledged",
          m.send(record_samples=pb.RecordSamples(on=False)).HasField("ack"))
    m.send(shutdown=pb.Shutdown())
    # The direct plane: a master that leaves while the soil waits for its
    # peer link frees the participant at once for the next session.
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    links = pb.Links(session=bytes(16), timeout_ms=20000)
    links.links.add(peer="track", interfaces=[0])
    check("links", m.send(links=links).HasField("ack"))
    m.id += 1
    w = pb.Envelope(id=m.id, window=pb.Window(first_step=0, end_step=5)).SerializeToString()
    m.s.sendall(struct.pack(">I", len(w)) + w)
    intruder = Master()  # not a peer: BUSY, and the soil waits on for its peer
    error(intruder.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master", participant="soil")),
          E.BUSY, "this participant serves a session; it accepts nothing but its peer links")
    m.s.close()
    t0 = time.monotonic()
    while True:
        m = Master()
        r = m.hello()
        if r is not None and r.HasField("hello_reply"):
            break
        check("freed within 2 s of the master leaving", time.monotonic() - t0 < 2, str(r))
        if time.monotonic() - t0 > 2:
            break
        time.sleep(0.05)
    check("shutdown", m.send(shutdown=pb.Shutdown()).HasField("ack"))
    check("closed after shutdown", m.receive() is None)
    # The accepting end under a flood: 100 connections that say nothing
    # while the soil waits for its peer do not hold up the real peer, whose
    # hello is answered (challenge, then HelloReply) within 1.5 s (the old
    # code: the whole link deadline); a
    # silent one is closed with TIMEOUT after its 2 s.
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    links = pb.Links(session=b"f" * 16, timeout_ms=20000)
    links.links.add(peer="track", interfaces=[0])
    check("links for the flood", m.send(links=links).HasField("ack"))
    m.id += 1
    w = pb.Envelope(id=m.id, window=pb.Window(first_step=0, end_step=1)).SerializeToString()
    m.s.sendall(struct.pack(">I", len(w)) + w)
    time.sleep(0.2)
    silent = [socket.create_connection(address, timeout=5) for _ in range(100)]
    t0 = time.monotonic()
    peer = Master()
    c = peer.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="peer", participant="soil",
                                 peer_of="track", session=b"f" * 16))
    check("the real peer is challenged under a flood", c is not None and
          c.HasField("challenge"), str(c))
    r = peer.send(auth=pb.Auth(mac=auth_answer(SECRET, "soil", c.challenge.nonce)))
    check("the real peer is answered under a flood", r is not None and
          r.HasField("hello_reply") and r.hello_reply.participant == "soil", str(r))
    check("within 1.5 s of 100 silent connections", time.monotonic() - t0 < 1.5,
          "%.2f s" % (time.monotonic() - t0))
    quiet = SessionMaster.__new__(SessionMaster)
    quiet.s, quiet.buf, quiet.id = silent[0], b"", 0
    late = quiet.receive()
    check("a silent connection is closed after its handshake time", late is not None and
          late.HasField("error") and late.error.code in (E.TIMEOUT, E.BUSY), str(late))
    for x in silent:
        x.close()
    peer.s.close()
    m.s.close()
    time.sleep(0.3)
    # The direct plane, the connecting end (here the soil connects to a
    # stand-in for the track): hello as a peer, the challenge answered with
    # the shared secret naming the track, PeerData at points 0 and 1, the
    # reports, WindowDone.
    peer_server = socket.socket()
    peer_server.bind(("127.0.0.1", 0))
    peer_server.listen(1)
    m, _ = configured()
    m.send(initialize=pb.Initialize(inputs=data(4)))
    links = pb.Links(session=b"k" * 16, timeout_ms=5000)
    links.links.add(peer="track", host="127.0.0.1", port=peer_server.getsockname()[1],
                    interfaces=[0])
    check("links to connect", m.send(links=links).HasField("ack"))
    m.id += 1
    w = pb.Envelope(id=m.id, window=pb.Window(first_step=0, end_step=1)).SerializeToString()
    m.s.sendall(struct.pack(">I", len(w)) + w)
    conn, _ = peer_server.accept()
    peer = SessionMaster.__new__(SessionMaster)
    peer.s, peer.buf, peer.id = conn, b"", 0
    conn.settimeout(5)
    h = peer.receive()
    check("peer hello", h.HasField("hello") and h.hello.role == "peer" and
          h.hello.participant == "track" and h.hello.peer_of == "soil" and
          h.hello.session == b"k" * 16, str(h))
    a = peer.send(challenge=pb.Challenge(nonce=bytes(32)))
    check("peer auth", a.HasField("auth") and a.auth.mac == auth_answer(SECRET, "track",
                                                                         bytes(32)), str(a))
    first = peer.send(hello_reply=pb.HelloReply(
        protocol_version=PROTOCOL_VERSION, participant="track",
        proof=auth_proof(SECRET, "track", h.hello.nonce, bytes(32))))
    check("the soil's outputs at point 0", first.HasField("peer_data") and
          first.peer_data.point == 0 and len(first.peer_data.data.interfaces) == 1 and
          len(first.peer_data.data.interfaces[0].displacement) == 4, str(first))
    after = peer.send(peer_data=pb.PeerData(point=0, data=data(4, 2e-4, 1e-3)))
    check("the soil's outputs at point 1", after.HasField("peer_data") and
          after.peer_data.point == 1 and not after.peer_data.last, str(after))
    reports = m.receive()
    check("reports", reports.id == m.id and reports.HasField("reports") and
          [r.step for r in reports.reports.reports] == [1], str(reports))
    done = m.receive()
    check("window done", done.id == m.id and done.HasField("window_done") and
          done.window_done.step == 1 and not done.window_done.reason, str(done))
    check("shutdown after the window", m.send(shutdown=pb.Shutdown()).HasField("ack"))
    check("closed after shutdown", m.receive() is None)
    conn.close()
    peer_server.close()
    m, r = configured(micro_steps=0)
    error(r, E.BAD_REQUEST, "configure: this soil integrates with fixed micro steps; set "
          "simulation.micro_steps in the scene")
finally:
    child.kill()
    child.wait()

if failures:
    sys.exit("FAILED:\n  " + "\n  ".join(failures))
print("python SDK session rules: all checks passed")
