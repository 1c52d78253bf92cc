#!/usr/bin/env python3
"""The Python SDK's lock step (docs/protocol.md §17, capability "lockstep"),
against the SDK example soil served in a child process over real sockets:
the capability offered with the direct plane and not with --relayed-only;
Window{lockstep} refused before Initialize (OUT_OF_ORDER) and by a
relayed-only participant (BAD_REQUEST), else answered Ack with its id; a
restore of a checkpoint never kept (OUT_OF_ORDER); steps taken again from
the kept checkpoint (Step flags, and Save{keep} / Restore{kept}) bit for bit
the steps taken again from a shipped State, reports and micro-step counts
alike; and a request of another kind (GetResults) answered as usual, ending
the lock step. Usage: python_lockstep_test.py SOURCE_DIR"""

import os
import sys
import tempfile

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk.wire import E, PROTOCOL_VERSION, pb  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sdk_session_support import Master, write_soil_config  # noqa: E402
from sdk_session_support import serve as support_serve  # noqa: E402

failures = []
H = 1e-4


def check(what, cond, detail=""):
    if not cond:
        failures.append("%s %s" % (what, detail))


work = tempfile.mkdtemp()
config = write_soil_config(work)


def serve(*options):
    return support_serve(src, config, *options)


def error(m, r, code, message):
    check("closed after the error", m.receive() is None)
    check("error %s" % E.Code.Name(code), r is not None and r.HasField("error")
          and r.error.code == code and r.error.message == message, str(r))


def data(n, d, v):
    c = pb.CouplingData()
    c.interfaces.add(displacement=[d * (1 + 0.1 * k) for k in range(n)],
                     velocity=[v * (1 - 0.2 * k) for k in range(n)])
    return c


def session(address, capabilities, initialize=True):
    m = Master(address)
    r = m.send(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="master",
                              participant="soil"))
    check("capabilities", list(r.hello_reply.capabilities) == capabilities, str(r))
    c = pb.Configure(participant="soil", macro_step=H, end_time=1e-3, micro_steps=10)
    i = c.interfaces.add(cut="ss", peer="track", stiffness=25.5e6, damping=4e4)
    i.x.extend([0.3 + 0.6 * k for k in range(4)])
    i.receives.extend([1, 2])
    i.sends.extend([1, 2])
    check("configured", m.send(configure=c).HasField("configured"))
    if initialize:
        check("initialized", m.send(initialize=pb.Initialize(inputs=data(4, 1e-4, 0.0)))
              .HasField("step_report"))
    return m


def step(m, n, k, **flags):
    """Macro step n with the k-th ramp of inputs; the reply's bytes."""
    r = m.send(step=pb.Step(step=n, t=n * H, h=H, inputs=data(4, 1e-4 * k, 1e-3 * k),
                            inputs_end=data(4, 1.5e-4 * k, -1e-3 * k), **flags))
    check("step %d" % n, r.HasField("step_report"), str(r))
    return r.step_report.SerializeToString()


def iterate(m, kept):
    """Three macro steps of three iterations each, taken again from a
    checkpoint: kept (lock step) or shipped (Save / Restore with the State);
    then one step whose inputs were held since the step before; the replies'
    bytes and the micro steps of the whole run."""
    out = []
    for n in range(3):
        state = None
        for k in range(3):
            if kept:
                out.append(step(m, n, n + k + 1, keep_checkpoint=k == 0,
                                restore_checkpoint=k > 0))
                continue
            if k == 0:
                state = m.send(save=pb.Save()).state
            else:
                check("restore", m.send(restore=pb.Restore(state=state)).HasField("ack"))
            out.append(step(m, n, n + k + 1))
    if kept:
        check("save keep", m.send(save=pb.Save(keep=True)).HasField("ack"))
        out.append(m.send(step=pb.Step(step=3, t=3 * H, h=H)).step_report.SerializeToString())
        check("restore kept", m.send(restore=pb.Restore(kept=True)).HasField("ack"))
    else:
        state = m.send(save=pb.Save()).state
        out.append(m.send(step=pb.Step(step=3, t=3 * H, h=H)).step_report.SerializeToString())
        check("restore", m.send(restore=pb.Restore(state=state)).HasField("ack"))
    out.append(m.send(step=pb.Step(step=3, t=3 * H, h=H)).step_report.SerializeToString())
    out.append(m.send(get_outputs=pb.GetOutputs(step=4)).outputs.SerializeToString())
    results = m.send(get_results=pb.GetResults())
    check("results after the lock step", results.HasField("results"), str(results))
    m.send(shutdown=pb.Shutdown())
    return out, results.results.SerializeToString()


child, address = serve()
quiet, quiet_address = serve("--relayed-only")
try:
    m = session(address, ["direct", "lockstep"], initialize=False)
    error(m, m.send(window=pb.Window(first_step=0, end_step=10, lockstep=True)),
          E.OUT_OF_ORDER, "a lock step needs initialize first")
    m = session(address, ["direct", "lockstep"])
    error(m, m.send(restore=pb.Restore(kept=True)), E.OUT_OF_ORDER,
          "restore of the kept checkpoint, but none was kept (a save with keep, or a step "
          "with keep_checkpoint, comes first)")
    m = session(quiet_address, [])
    error(m, m.send(window=pb.Window(first_step=0, end_step=10, lockstep=True)),
          E.BAD_REQUEST, "this participant does not serve the direct data plane "
          "(--relayed-only), so no lock step either")

    shipped = iterate(session(address, ["direct", "lockstep"]), False)
    m = session(address, ["direct", "lockstep"])
    r = m.send(window=pb.Window(first_step=0, end_step=10, lockstep=True))
    check("lock step entered", r.HasField("ack") and r.id == m.id, str(r))
    kept = iterate(m, True)
    check("as many replies", len(kept[0]) == len(shipped[0]) == 12, str(len(kept[0])))
    for k, (a, b) in enumerate(zip(shipped[0], kept[0])):
        check("reply %d bitwise the same from the kept checkpoint" % k, a == b)
    check("the iterations differ (the test can see a wrong restore)",
          shipped[0][0] != shipped[0][1] and shipped[0][1] != shipped[0][2])
    check("results and micro steps the same", shipped[1] == kept[1])
finally:
    for c in (child, quiet):
        c.kill()
        c.wait()

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("the lock step of the Python SDK: all checks passed")
