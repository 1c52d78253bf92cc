#!/usr/bin/env python3
"""Substep waveforms in the Python SDK (docs/protocol.md, "Substep
waveforms"), against the SDK example soil served in a child process over
real sockets: `Sampled.at` exact for polynomials of its degree; RecordSamples
acknowledged, and a step's report then carrying the outputs at the step's
start and after each of its 10 micro steps; a step with waveforms bit for
bit a step with the ramp between the same ends when the waveform is that
ramp; and the refusals, each naming the sender and closing the session: too
many samples (checked before anything is allocated), a sample outside the
window, inputs beside waveforms, and a participant that takes none.
Usage: python_waveform_test.py SOURCE_DIR"""

import os
import subprocess
import sys
import tempfile

import numpy as np

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk.waveforms import Sampled  # noqa: E402
from railcosim_sdk.wire import E, PROTOCOL_VERSION, pb  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sdk_session_support import Master, write_soil_config  # noqa: E402
from sdk_session_support import serve as support_serve  # noqa: E402

failures = []
H = 1e-4
POINTS = 4


def check(what, cond, detail=""):
    if not cond:
        failures.append("%s %s" % (what, detail))


# Exact for every polynomial of its degree, anywhere in the window (and
# beyond the samples, where the end stencil extrapolates).
times = np.array([0.0, 0.1, 0.35, 0.5, 0.8, 1.0])
for degree in range(4):
    def poly(t):
        return np.array([sum((k + 1) * t ** k for k in range(degree + 1)), 2.0 - t ** degree])
    w = Sampled(times, np.array([poly(t) for t in times]), degree, 0.0, 1.0)
    worst = max(float(np.abs(w.at(t) - poly(t)).max()) for t in np.linspace(-0.05, 1.05, 45))
    check("degree %d exact" % degree, worst <= 1e-13, "off by %g" % worst)
one = Sampled(np.array([0.2]), np.array([[3.0, 4.0]]), 3, 0.0, 1.0)  # one sample: held
check("one sample held", list(one.at(0.9)) == [3.0, 4.0] and list(one.start) == [3.0, 4.0])

work = tempfile.mkdtemp()
config = write_soil_config(work)


def session(address, record=True):
    m = Master(address)
    m.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master", participant="soil"))
    c = pb.Configure(participant="soil", macro_step=H, end_time=1e-3, micro_steps=10)
    i = c.interfaces.add(cut="ss", peer="track", stiffness=25.5e6, damping=4e4)
    i.x.extend([0.3 + 0.6 * k for k in range(POINTS)])
    i.receives.extend([1, 2])
    i.sends.extend([1, 2])
    check("configured", m.send(configure=c).HasField("configured"))
    start = pb.CouplingData()
    start.interfaces.add(displacement=[1e-4] * POINTS, velocity=[0.0] * POINTS)
    check("initialized", m.send(initialize=pb.Initialize(inputs=start)).HasField("step_report"))
    if record:
        r = m.send(record_samples=pb.RecordSamples(on=True))
        check("record_samples answered", r.HasField("ack"), str(r))
    return m


def ramp(n, t):
    """A linear input over step n: displacements then velocities, per point."""
    s = (t - n * H) / H
    return [1e-4 * (1 + 0.1 * k) * (1 + s) for k in range(POINTS)] + \
        [1e-3 * (1 - 0.2 * k) * (1 - 2 * s) for k in range(POINTS)]


def waveform(n, ts, degree=3):
    w = pb.InputWaveforms()
    w.interfaces.add(degree=degree, width=2 * POINTS, times=ts,
                     values=[v for t in ts for v in ramp(n, t)])
    return w


def error(m, r, code, message):
    check("error %s" % E.Code.Name(code), r is not None and r.HasField("error")
          and r.error.code == code and r.error.message == message, str(r))
    check("closed after the error", m.receive() is None)


child, address = support_serve(src, config)
plain = os.path.join(work, "plain.py")
with open(plain, "w") as f:
    f.write("import runpy\nns = runpy.run_path(%r)\nclass Plain(ns['LumpedSoil']):\n"
            "    takes_waveforms = False\nns['rc'].serve(Plain())\n"
            % os.path.join(src, "examples", "python_soil", "soil_participant.py"))
plain_child = subprocess.Popen(["/usr/bin/python3", plain, "--config", config],
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
line = plain_child.stdout.readline()
check("the plain soil listens", line.startswith("listening on "), line)
host, port = line.split()[-1].rsplit(":", 1)
plain_address = (host, int(port))
try:
    # Samples: the step's start and its 10 micro steps, times increasing.
    m = session(address)
    ts = [n * H / 4 for n in range(5)]
    r = m.send(step=pb.Step(step=0, t=0.0, h=H, waveforms=waveform(0, ts)))
    samples = r.step_report.samples
    got = [s.t for s in samples]
    check("11 samples", len(got) == 11 and got[0] == 0.0 and abs(got[-1] - H) < 1e-15
          and all(b > a for a, b in zip(got, got[1:])), str(got))
    check("last sample the report's outputs", len(samples) == 11 and
          samples[-1].outputs.SerializeToString() == r.step_report.outputs.SerializeToString())
    via_waveform = r.step_report.outputs.SerializeToString()
    m.send(shutdown=pb.Shutdown())
    # The same step with the same line given as a ramp: the soil takes its
    # loads at the micro steps' ends either way; the states agree to rounding.
    m = session(address, record=False)
    a, b = pb.CouplingData(), pb.CouplingData()
    a.interfaces.add(displacement=ramp(0, 0.0)[:POINTS], velocity=ramp(0, 0.0)[POINTS:])
    b.interfaces.add(displacement=ramp(0, H)[:POINTS], velocity=ramp(0, H)[POINTS:])
    r = m.send(step=pb.Step(step=0, t=0.0, h=H, inputs=a, inputs_end=b))
    check("a ramp's step has no samples", len(r.step_report.samples) == 0)
    x = pb.CouplingData.FromString(via_waveform).interfaces[0].displacement
    y = r.step_report.outputs.interfaces[0].displacement
    check("the waveform's step is the ramp's", max(abs(p - q) for p, q in zip(x, y))
          <= 1e-12 * max(abs(q) for q in y), "%s %s" % (list(x), list(y)))
    m.send(shutdown=pb.Shutdown())

    # Too many samples: refused by count, before the values are read.
    m = session(address)
    many = pb.InputWaveforms()
    many.interfaces.add(degree=1, width=2 * POINTS, times=[0.0] * 65538)
    error(m, m.send(set_inputs=pb.SetInputs(step=0, t=0.0, waveforms=many)), E.BAD_REQUEST,
          "macro step 0: the waveform of input interface 0 (ss, the outputs of track, sent by "
          "the master) has 65538 samples; 1 to 65537 are allowed (one per micro step and one "
          "more)")
    # A sample past the window by more than H / 1000.
    m = session(address)
    late = waveform(0, [0.0, H / 2, H * 1.002])
    error(m, m.send(step=pb.Step(step=0, t=0.0, h=H, waveforms=late)), E.BAD_REQUEST,
          "macro step 0: the waveform of input interface 0 (ss, the outputs of track, sent by "
          "the master): sample 2 at t = 0.0001002 s lies outside the macro step [0, 0.0001] s "
          "(tolerance 1e-07 s)")
    # Inputs beside waveforms.
    m = session(address)
    error(m, m.send(step=pb.Step(step=0, t=0.0, h=H, inputs=a, waveforms=waveform(0, ts))),
          E.BAD_REQUEST, "macro step 0: inputs and waveforms in one message; send one of them")
    # A participant that takes none refuses the recording, naming itself.
    m = session(plain_address, record=False)
    error(m, m.send(record_samples=pb.RecordSamples(on=True)), E.BAD_REQUEST,
          "participant soil takes no substep waveforms (its class does not set "
          "takes_waveforms): run it with --inputs hold or linear, not waveform0 to waveform3")
finally:
    for c in (child, plain_child):
        c.kill()
        c.wait()

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("python_waveform_test: ok")
