"""Progress of the ground-vibration study on stderr (never stdout): runs
done of all, the macro step of the run under way, the time elapsed and an
estimate of the time left. On a terminal one line redrawn in place at most
five times a second; otherwise a plain line every RAILCOSIM_PROGRESS_SECONDS
seconds (default 30), beginning "progress: ", as `master run` and `master
study` write theirs (master/run/progress.hpp).

A master run started by the study writes its own plain lines to a pipe
(RAILCOSIM_PROGRESS_SECONDS=1 for it); STEP_LINE reads the step from them."""
import os
import re
import sys
import time

# The step of a master run's plain progress line: "CASE step DONE/TOTAL".
STEP_LINE = re.compile(r"^progress: .* step (\d+)/(\d+);")


def clock(seconds):
    s = int(round(max(0.0, seconds)))
    return "%d:%02d:%02d" % (s // 3600, s // 60 % 60, s % 60) if s >= 3600 else "%d:%02d" % (s // 60, s % 60)


def plain_period():
    try:
        v = float(os.environ.get("RAILCOSIM_PROGRESS_SECONDS", ""))
        return v if v > 0 and v == v and v != float("inf") else 30.0
    except ValueError:
        return 30.0


class Progress:
    def __init__(self, what, runs, stream=None, clock_fn=time.monotonic):
        self.what, self.runs, self.done = what, runs, 0
        self.stream = stream if stream is not None else sys.stderr
        self.terminal = self.stream.isatty()
        self.period = 0.2 if self.terminal else plain_period()
        self.now = clock_fn
        self.start = self.last = self.now()
        self.run, self.step, self.steps = "", 0, 0
        self.drawn = False

    def line(self, elapsed):
        text = "%s: %d/%d run%s done" % (self.what, self.done, self.runs, "" if self.runs == 1 else "s")
        fraction = float(self.done)
        if self.run:
            text += "; %s" % self.run
            if self.steps > 0:
                text += " step %d/%d" % (self.step, self.steps)
                fraction += self.step / self.steps
        fraction /= max(1, self.runs)
        text += "; elapsed %s" % clock(elapsed)
        if 0.01 <= fraction < 1.0:
            text += ", about %s left" % clock(elapsed * (1.0 - fraction) / fraction)
        elif fraction < 1.0:
            text += ", time left not yet known"
        return text

    def draw(self, force=False):
        now = self.now()
        if not force and now - self.last < self.period:
            return
        self.last = now
        text = self.line(now - self.start)
        if self.terminal:
            self.stream.write("\r%s\033[K" % text)
            self.drawn = True
        else:
            self.stream.write("progress: %s\n" % text)
        self.stream.flush()

    def begin(self, run):
        """A run starts (its name; its steps not yet known)."""
        self.run, self.step, self.steps = run, 0, 0
        self.draw(force=self.terminal)

    def at(self, step, steps):
        self.step, self.steps = step, steps
        self.draw()

    def run_done(self):
        self.done += 1
        self.run, self.step, self.steps = "", 0, 0
        self.draw(force=self.terminal)

    def say(self, text, out=None):
        """A line of its own on `out` (stdout by default), the progress line
        cleared first and drawn again below it on a terminal."""
        out = out if out is not None else sys.stdout
        if self.terminal and self.drawn:
            self.stream.write("\r\033[K")
            self.stream.flush()
        out.write(text + "\n")
        out.flush()
        if self.terminal and self.drawn:
            self.draw(force=True)

    def end(self):
        if self.terminal and self.drawn:
            self.draw(force=True)
            self.stream.write("\n")
            self.stream.flush()
        self.drawn = False
