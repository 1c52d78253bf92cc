"""Progress frames (Configure.progress_ms, docs/protocol.md §9): while the
participant's advance() works on a request, a Progress frame with the
request's id, the macro step and the participant's micro-step count
(self.micro_steps, which the author keeps up to date) every
max(progress_ms, 100) ms, but only when the count has advanced since the
last frame: the master counts only frames that advance, so a participant
that works long keeps its step deadline and one that is stuck does not.
While its statics() works, the same with step -1 and the count
self.static_iterations (solver iterations, say), which keeps the master's
reply limit."""

import threading

from .wire import pb

MIN_INTERVAL_MS = 100


class Ticker:
    """A context around one advance() or statics(): sends the frames from a
    thread of its own while the session's thread is inside the call (the
    only time that thread does not use the master's channel); stopped and
    joined before the session sends its reply."""

    def __init__(self, session, step, counter="micro_steps"):
        self.session = session
        self.step = step
        self.counter = counter  # the participant's attribute the frames carry
        self.thread = None
        self.stop = None  # a threading.Event, made only when frames are due

    def __enter__(self):
        s = self.session
        ms = getattr(s, "progress_ms", 0)
        if ms > 0 and s.master is not None and s.request_id:
            self.interval = max(ms, MIN_INTERVAL_MS) / 1000.0
            self.last = getattr(s.p, self.counter, 0)
            self.stop = threading.Event()
            self.thread = threading.Thread(target=self.run, daemon=True)
            self.thread.start()
        return self

    def __exit__(self, *exc):
        if self.thread is not None:
            self.stop.set()
            self.thread.join()
        return False

    def run(self):
        s = self.session
        while not self.stop.wait(self.interval):
            now = getattr(s.p, self.counter, 0)
            if not isinstance(now, int) or now <= self.last:
                continue
            self.last = now
            frame = pb.Envelope(id=s.request_id,
                                progress=pb.Progress(step=self.step, micro_steps=now))
            try:
                s.master.send(frame)
            except Exception:  # noqa: BLE001  (the reply's send meets the same error)
                return
