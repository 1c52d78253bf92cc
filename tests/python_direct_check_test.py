#!/usr/bin/env python3
"""The Python SDK's direct plane checks a peer's values for being finite
once, when its frame arrives, except in a peer's last data (which a
diverging peer may send): such data must still be checked before the
participant steps on it. A unit test of the plane with its channels
replaced by lists of frames: a last frame with a NaN is refused at the step
that would use it (BAD_REQUEST naming the interface), and the participant
never steps on it; the same frame without the NaN is stepped on.
Usage: python_direct_check_test.py SOURCE_DIR"""

import os
import sys
import time

src = sys.argv[1]
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk.direct import Link  # noqa: E402
from railcosim_sdk.wire import E, pb  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sdk_session_support import Frames, configured_session, example_soil, run_window  # noqa: E402

SOIL = example_soil(src)
N, H = 4, 1e-4


def data(value):
    d = pb.CouplingData()
    d.interfaces.add(displacement=[value] * N, velocity=[0.0] * N)
    return d


def steps_on(value):
    """Runs a window of two steps whose peer's second frame is its last, the
    displacement `value`; returns (the participant's macro step after it,
    the error or None)."""
    s = configured_session(SOIL, N, H)
    s.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=data(1e-4))))
    # A link whose peer is a step ahead: step n takes the peer's point n + 1,
    # so the last data (point 1) is what step 0 steps on.
    link = Link(pb.PeerLink(peer="track", interfaces=[0], ahead=True))
    link.chan = Frames([pb.Envelope(peer_data=pb.PeerData(point=0, data=data(1e-4))),
                        pb.Envelope(peer_data=pb.PeerData(point=1, data=data(value),
                                                          last=True))])
    _, error = run_window(s, link, Frames())
    return s.step, error


failures = []
step, error = steps_on(float("nan"))
if step != 0 or error is None or error.code != E.BAD_REQUEST or \
        "interface ss: a displacement value is not finite" not in str(error):
    failures.append("a NaN in a peer's last data: stepped to %d, error %r" % (step, error))
step, error = steps_on(2e-4)
if step != 1 or error is not None:
    failures.append("a peer's finite last data: stepped to %d, error %r" % (step, error))
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("python_direct_check_test: ok")
