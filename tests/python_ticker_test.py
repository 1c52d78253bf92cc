#!/usr/bin/env python3
"""The Python SDK's progress frames without a thread per macro step: 500
quick macro steps with progress frames due (Configure.progress_ms as the
master sends it, a master channel attached) start at most one thread in
all and send no frame; a step that works 0.35 s with its micro-step count
advancing sends frames with the request's id, the step and the count, every
interval and none once the step has returned; a stuck step (the count does
not move) sends none; and a send that is slow does not let the next reply
overtake it. Usage: python_ticker_test.py SOURCE_DIR"""

import os
import sys
import threading
import time
import unittest

SRC = os.path.abspath(sys.argv.pop(1))
sys.path.insert(0, os.path.join(SRC, "sdk", "python"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from railcosim_sdk.wire import pb  # noqa: E402
from sdk_session_support import configured_session, example_soil  # noqa: E402

SOIL = example_soil(SRC)
H = 1e-4


class Master:
    """The master's channel: keeps every Envelope sent and when; a send may be slow."""

    def __init__(self, delay=0.0):
        self.sent, self.delay, self.lock = [], delay, threading.Lock()

    def send(self, env):
        time.sleep(self.delay)
        with self.lock:
            self.sent.append((time.monotonic(), env))

    def progress(self):
        with self.lock:
            return [e for _, e in self.sent if e.WhichOneof("body") == "progress"]


class Working(SOIL["LumpedSoil"]):
    """The example soil; at macro step `slow` it works `seconds`, its count
    advancing every 10 ms when `advancing`."""
    slow, seconds, advancing = -1, 0.0, True

    def advance(self, t, H, inputs):
        if round(t / H) == self.slow:
            end = time.monotonic() + self.seconds
            while time.monotonic() < end:
                time.sleep(0.01)
                if self.advancing:
                    self.micro_steps += 1
        return super().advance(t, H, inputs)


def session(master, progress_ms=100):
    s = configured_session(SOIL, 8, H)
    s.p.__class__ = Working
    s.progress_ms = progress_ms  # as Configure.progress_ms sets it
    s.master = master
    s.handle(pb.Envelope(id=3, initialize=pb.Initialize(inputs=inputs())))
    return s


def inputs():
    d = pb.CouplingData()
    w = d.interfaces.add()
    w.displacement.extend([1e-4] * 8)
    w.velocity.extend([0.0] * 8)
    return d


def step(s, n, req_id):
    """A Step as the server answers it: the request's id set around handle()."""
    s.request_id = req_id
    reply = s.handle(pb.Envelope(id=req_id, step=pb.Step(step=n, t=n * H, h=H, inputs=inputs())))
    s.request_id = 0
    return reply


class Ticker(unittest.TestCase):
    def test_quick_steps_start_at_most_one_thread(self):
        made = []
        real = threading.Thread.__init__

        def counting(self, *a, **k):
            made.append(k.get("name"))
            real(self, *a, **k)

        m = Master()
        s = session(m)
        threading.Thread.__init__ = counting
        try:
            for n in range(500):
                step(s, n, 100 + n)
        finally:
            threading.Thread.__init__ = real
        self.assertLessEqual(len(made), 1, "%d threads started" % len(made))
        self.assertEqual(m.progress(), [])  # no step lasted an interval

    def test_long_step_sends_frames_while_it_works_and_none_after(self):
        m = Master()
        s = session(m)
        s.p.slow, s.p.seconds = 2, 0.35
        for n in range(2):
            step(s, n, 10 + n)
        before = s.p.micro_steps
        step(s, 2, 77)
        returned = time.monotonic()
        frames = m.progress()
        self.assertGreaterEqual(len(frames), 2, frames)  # 0.35 s at 0.1 s: 3 frames due
        self.assertLessEqual(len(frames), 4, frames)
        for f in frames:
            self.assertEqual(f.id, 77)
            self.assertEqual(f.progress.step, 2)
            self.assertGreater(f.progress.micro_steps, before)
        counts = [f.progress.micro_steps for f in frames]
        self.assertEqual(counts, sorted(set(counts)))  # every frame advances
        for n in range(3, 40):  # quick steps after it: no more frames
            step(s, n, 100 + n)
        time.sleep(0.25)
        self.assertEqual(len(m.progress()), len(frames))
        self.assertTrue(all(t <= returned for t, _ in m.sent))

    def test_stuck_step_sends_nothing(self):
        m = Master()
        s = session(m)
        s.p.slow, s.p.seconds, s.p.advancing = 0, 0.35, False
        step(s, 0, 5)
        self.assertEqual(m.progress(), [])

    def test_no_frames_when_progress_is_not_asked(self):
        m = Master()
        s = session(m, progress_ms=0)
        s.p.slow, s.p.seconds = 0, 0.25
        step(s, 0, 5)
        self.assertEqual(m.progress(), [])

    def test_a_slow_send_ends_before_the_call_returns(self):
        m = Master(delay=0.15)
        s = session(m)
        s.p.slow, s.p.seconds = 0, 0.12  # the frame at 0.1 s is still being sent at 0.12 s
        step(s, 0, 9)
        returned = time.monotonic()
        frames = m.sent
        self.assertEqual(len(frames), 1, frames)
        self.assertLessEqual(frames[0][0], returned)


if __name__ == "__main__":
    unittest.main()
