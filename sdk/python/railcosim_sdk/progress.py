"""Progress frames (Configure.progress_ms, docs/protocol.md §9): while the
participant's advance() works on a request, a Progress frame with the
request's id, the macro step and the participant's micro-step count
(self.micro_steps, which the author keeps up to date) every
max(progress_ms, 100) ms, but only when the count has advanced since the
last frame: the master counts only frames that advance, so a participant
that works long keeps its step deadline and one that is stuck does not.
While its statics() works, the same with step -1 and the count
self.static_iterations (solver iterations, say), which keeps the master's
reply limit.

One timer thread for the whole process sends them, started the first time
frames are due and kept for the process's life: a call registers itself on
entry and leaves on exit, so a macro step costs a lock and a few
assignments, not a thread. The timer wakes when the earliest registered
call's next frame is due (at most once per interval, however many macro
steps run in it), and sleeps without a timeout while no call is
registered."""

import threading
import time

from .wire import pb

MIN_INTERVAL_MS = 100


class _Timer:
    """The process's one timer thread and the calls registered with it."""

    def __init__(self):
        self.cond = threading.Condition()
        self.calls = set()    # Ticker objects inside their call
        self.thread = None
        self.idle = False     # the thread waits without a timeout (no call registered)
        self.sending = None   # the Ticker whose frame is being sent (outside the lock)

    def add(self, ticker):
        with self.cond:
            self.calls.add(ticker)
            if self.thread is None:
                self.thread = threading.Thread(target=self.run, name="railcosim-progress",
                                               daemon=True)
                self.thread.start()
            elif self.idle:
                self.cond.notify()

    def remove(self, ticker):
        """Ends the ticker's frames: when this returns, none of its frames is
        being sent or will be (the caller's reply goes on the same channel)."""
        with self.cond:
            self.calls.discard(ticker)
            while self.sending is ticker:
                self.cond.wait()

    def run(self):
        with self.cond:
            while True:
                if not self.calls:
                    self.idle = True
                    self.cond.wait()
                    self.idle = False
                    continue
                now = time.monotonic()
                due = min(self.calls, key=lambda t: t.due)
                if due.due > now:
                    self.cond.wait(due.due - now)
                    continue
                due.due = now + due.interval
                frame = due.frame()
                if frame is None:
                    continue
                self.sending = due
                self.cond.release()
                try:
                    due.session.master.send(frame)
                except Exception:  # noqa: BLE001  (the reply's send meets the same error)
                    due.failed = True
                finally:
                    self.cond.acquire()
                    self.sending = None
                    self.cond.notify_all()


_timer = _Timer()


class Ticker:
    """A context around one advance() or statics(): while the session's
    thread is inside the call (the only time that thread does not use the
    master's channel), the process's timer sends the frames; on exit they
    have stopped, before the session sends its reply."""

    __slots__ = ("session", "step", "counter", "interval", "due", "last", "failed", "active")

    def __init__(self, session, step, counter="micro_steps"):
        self.session = session
        self.step = step
        self.counter = counter  # the participant's attribute the frames carry
        self.active = False     # registered with the timer (frames due)
        self.failed = False     # a frame's send failed: no more frames

    def __enter__(self):
        s = self.session
        ms = getattr(s, "progress_ms", 0)
        if ms > 0 and s.master is not None and s.request_id:
            self.interval = max(ms, MIN_INTERVAL_MS) / 1000.0
            self.last = getattr(s.p, self.counter, 0)
            self.due = time.monotonic() + self.interval
            self.active = True
            _timer.add(self)
        return self

    def __exit__(self, *exc):
        if self.active:
            _timer.remove(self)
            self.active = False
        return False

    def frame(self):
        """The frame due now, or None (the count has not advanced; a send failed)."""
        now = getattr(self.session.p, self.counter, 0)
        if self.failed or not isinstance(now, int) or now <= self.last:
            return None
        self.last = now
        return pb.Envelope(id=self.session.request_id,
                           progress=pb.Progress(step=self.step, micro_steps=now))
