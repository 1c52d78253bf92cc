#!/usr/bin/env python3
"""The Python SDK reads and writes an interface's coupling data through the
layout its serialisation has when it holds exactly the interface's
quantities, n values each (packed.Layout); anything else takes the generic
path. Unit tests of that split: the layout's view gives the values bit for
bit and refuses every other shape (a missing or extra quantity, counts that
differ though the total size is the same); the StepReports and reports'
frames the direct plane writes by hand read as protobuf's, and as the
relayed plane's reports of the same steps; a session refuses inputs that
are not finite or do not fit with the same messages either way, relayed
and from a peer on the direct plane; a report's `finite` flag sees a
non-finite value in any quantity sent. Usage: python_sdk_layout_test.py SOURCE_DIR"""

import os
import sys
import time

import numpy as np

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk import packed  # noqa: E402
from railcosim_sdk.direct import Link  # noqa: E402
from railcosim_sdk.wire import E, ProtocolError, pb  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sdk_session_support import Frames, configured_session, example_soil, run_window  # noqa: E402

SOIL = example_soil(src)
N, H = 4, 1e-4
failures = []


def check(what, cond, detail=""):
    if not cond:
        failures.append("%s %s" % (what, detail))


def raw(**q):
    return pb.InterfaceData(**q).SerializeToString()


# The layout's view: the values bit for bit, in field order, as a view.
d, v = np.array([1e-3, -2.5, 3e300, 5e-324]), np.array([0.0, -0.0, 7.0, 1.0 / 3.0])
layout = packed.Layout(("velocity", "displacement"), N)
got = layout.view(raw(displacement=d, velocity=v))
check("view: names in field order", layout.names == ("displacement", "velocity"), layout.names)
check("view: the values bit for bit", got is not None and got.shape == (2, N) and
      got[0].tobytes() == d.tobytes() and got[1].tobytes() == v.tobytes(), repr(got))
for name, other in (("one quantity missing", raw(displacement=d)),
                    ("an extra quantity", raw(displacement=d, velocity=v, force=d)),
                    ("counts 5 and 3, the same total size",
                     raw(displacement=[1.0] * 5, velocity=[1.0] * 3)),
                    ("one value fewer each", raw(displacement=d[:3], velocity=v[:3])),
                    ("nothing", b"")):
    check("view refuses %s" % name, layout.view(other) is None)
check("encode is the serialisation", layout.encode({"displacement": d, "velocity": v}) ==
      raw(displacement=d, velocity=v))


def session():
    s = configured_session(SOIL, N, H)
    return s


def data(**q):
    c = pb.CouplingData()
    c.interfaces.add(**q)
    return c


ok = dict(displacement=[1e-4] * N, velocity=[0.0] * N)
nan_v = dict(displacement=[1e-4] * N, velocity=[0.0, 0.0, float("nan"), 0.0])
inf_d = dict(displacement=[1e-4, float("-inf"), 0.0, 0.0], velocity=[0.0] * N)
extra = dict(displacement=[1e-4] * N, velocity=[0.0] * N, force=[1.0] * N)
odd = dict(displacement=[1e-4] * (N + 1), velocity=[0.0] * (N - 1))
for name, q, message in (
        ("a NaN velocity", nan_v, "interface ss: a velocity value is not finite"),
        ("an infinite displacement", inf_d, "interface ss: a displacement value is not finite"),
        ("an extra force", extra, "interface ss: force given, but the interface does not "
         "receive it"),
        ("counts 5 and 3", odd, "interface ss: 5 displacement values, expected 4 (one per "
         "coupling point)")):
    s = session()
    s.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=data(**ok))))
    try:
        s.handle(pb.Envelope(id=4, step=pb.Step(step=0, h=H, inputs=data(**q))))
        failures.append("relayed, %s: stepped on" % name)
    except ProtocolError as e:
        check("relayed, %s" % name, e.code == E.BAD_REQUEST and str(e) == message, str(e))

# The inputs a step takes are the values sent, bit for bit.
s = session()
s.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=data(**ok))))
s.set_inputs(data(displacement=d, velocity=v).interfaces)
check("held inputs bit for bit", s.held[0].displacement.start.tobytes() == d.tobytes() and
      s.held[0].velocity.start.tobytes() == v.tobytes())

# A report's finite flag, for a non-finite value in each quantity sent.
s = session()
s.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=data(**ok))))
for q in ("displacement", "velocity"):
    out = {"displacement": np.full(N, 1e-4), "velocity": np.zeros(N)}
    check("finite report", s.report([dict(out)], 1).finite)
    out[q] = out[q].copy()
    out[q][N - 1] = float("inf")
    r = s.report([out], 1)
    check("a report with an infinite %s is not finite" % q, not r.finite)
    check("its values as sent", r.outputs.interfaces[0].SerializeToString() == raw(**out))


# A StepReport and the reports' frame written by hand read as the messages
# protobuf writes.
for step, t, peak, fin, hist in ((7, 7e-4, 1.5e-3, True, [0.25, -1.0]),
                                (0, -0.0, float("inf"), False, []),
                                (2**40 + 3, 1e300, 0.0, True, [5e-324])):
    mine = packed.step_report(step, t, [layout.encode({"displacement": d, "velocity": v})],
                              peak, fin, hist)
    theirs = pb.StepReport(step=step, t=t, max_abs_displacement=peak, finite=fin, history=hist)
    theirs.outputs.interfaces.add(displacement=d, velocity=v)
    check("step_report %d" % step, pb.StepReport.FromString(mine).SerializeToString() ==
          theirs.SerializeToString(), repr(pb.StepReport.FromString(mine)))
    for waiting in ("", "track"):
        frame = pb.Envelope.FromString(packed.reports(300 + step, [mine, mine], waiting))
        check("reports %d %r" % (step, waiting), frame.id == 300 + step and
              frame.reports.waiting_for == waiting and len(frame.reports.reports) == 2 and
              all(r.SerializeToString() == theirs.SerializeToString()
                  for r in frame.reports.reports), str(frame))


def direct(q):
    """A window of two steps whose peer sends `q` at point 1 (not its last):
    the participant's macro step after it, and the error or None."""
    s = session()
    s.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=data(**ok))))
    link = Link(pb.PeerLink(peer="track", interfaces=[0]))
    link.chan = Frames([pb.Envelope(peer_data=pb.PeerData(point=0, data=data(**ok))),
                        pb.Envelope(peer_data=pb.PeerData(point=1, data=data(**q)))])
    master = Frames()
    plane, error = run_window(s, link, master)
    if error is not None:
        return s.step, error
    plane.flush()
    # The reports the master was sent: those of a relayed session on the same data.
    relayed = session()
    relayed.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=data(**ok))))
    for n, q in enumerate((ok, ok)):
        want = relayed.handle(pb.Envelope(id=4 + n, step=pb.Step(step=n, h=H, inputs=data(
            **q)))).step_report
        got = [r for f in master.sent for r in f.reports.reports]
        check("direct: the report of step %d" % n, len(got) == 2 and all(
            f.id == 1 for f in master.sent) and got[n].SerializeToString() ==
            want.SerializeToString(), str(got))
    return s.step, None


step, e = direct(ok)
check("direct: two steps on finite data", step == 2 and e is None, "%d %r" % (step, e))
step, e = direct(nan_v)
check("direct: a peer's NaN velocity refused before the step that uses it",
      step == 1 and e is not None and e.code == E.PEER_FAILED and e.sender == "track" and
      str(e) == "the track participant sent a non-finite value for point 1 at macro step 1 "
      "(t = 0.0001 s)", "%d %r" % (step, e))
for name, q, message in (
        ("an extra force", extra, "interface ss: force given, but the interface does not "
         "receive it"),
        ("counts 5 and 3", odd, "interface ss: 5 displacement values, expected 4 (one per "
         "coupling point)")):
    step, e = direct(q)
    check("direct: %s" % name, step == 1 and e is not None and e.code == E.BAD_REQUEST and
          str(e) == message, "%d %r" % (step, e))

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("python_sdk_layout_test: ok")
