"""Substep waveforms (docs/protocol.md, "Substep waveforms"): the inputs of a
macro step as their senders' samples, evaluated at any time of the window,
and the samples this participant records of its own outputs.

A participant takes them when its class sets `takes_waveforms = True`: the
session then acknowledges RecordSamples, decodes the `waveforms` of SetInputs
and Step into `Sampled` quantities (each with `at(t)`, `start`, `end`), and
sends the samples the participant records with `record(t, outputs)` in its
step's report.
"""

import numpy as np

from . import packed
from . import participant as api
from .wire import E, ProtocolError, pb

# The least sample count a waveform may have at most (the built-in nodes'
# largest number of micro steps in one macro step, plus the step's start).
MIN_SAMPLE_LIMIT = 65536 + 1


class Sampled:
    """An input quantity over [t0, t0 + H] as its sender's samples: `at(t)`
    interpolates them locally with Lagrange polynomials of `degree` (the
    degree + 1 samples nearest to t; fewer samples, lower degree; beyond
    the samples the end stencil extrapolates), as the built-in nodes do
    (common/waveform). `start` and `end` are the values at t0 and t0 + H;
    `held` is False. `times` and `values` (samples x points) are the data."""

    __slots__ = ("times", "values", "degree", "t0", "H", "start", "end", "held")

    def __init__(self, times, values, degree, t0, H):
        self.times, self.values, self.t0, self.H = times, values, t0, H
        self.degree = min(degree, len(times) - 1)
        self.held = False
        self.start = self.at(t0)
        self.end = self.at(t0 + H)

    def at(self, t):
        times, n, p = self.times, len(self.times), self.degree
        j = int(np.searchsorted(times, t, side="right")) - 1  # times[j] <= t < times[j + 1]
        j = min(max(j, 0), n - 1)
        if p == 0:
            return self.values[j].copy()
        first = min(max(j - (p - 1) // 2, 0), n - p - 1)
        out = np.zeros(self.values.shape[1])
        for a in range(first, first + p + 1):
            w = 1.0  # the Lagrange basis polynomial of sample a at t
            for b in range(first, first + p + 1):
                if b != a:
                    w *= (t - float(times[b])) / (float(times[a]) - float(times[b]))
            out += w * self.values[a]
        return out

    def rate(self):
        """The mean rate over the step, (end - start) / H."""
        return (self.end - self.start) / self.H


def sample_limit(run):
    """The most samples one waveform may bring (Configure's max_micro_steps + 1)."""
    return max(int(run.max_micro_steps), MIN_SAMPLE_LIMIT - 1) + 1


def decode(session, n, waveforms):
    """A list of api.Inputs (one per interface) from an InputWaveforms for
    macro step n; refuses, naming where the data came from, what does not fit."""
    ifs = session.interfaces
    at = "macro step %d: " % n
    if len(waveforms.interfaces) != len(ifs):
        raise ProtocolError(E.BAD_REQUEST, at + "waveforms for %d interfaces; participant %s "
                            "has %d" % (len(waveforms.interfaces), session.p.name, len(ifs)))
    H = session.H
    t0, t1, slack = n * H, (n + 1) * H, 1e-3 * H
    limit = sample_limit(session.p.run)
    out = []
    for k, (i, w) in enumerate(zip(ifs, waveforms.interfaces)):
        of = at + "the waveform of input interface %d (%s, the outputs of %s, sent by the " \
            "master)" % (k, i.cut, i.peer or "its peer")
        width = i.n * len(i.receives)
        count = len(w.times)
        if w.width != width:
            raise ProtocolError(E.BAD_REQUEST, "%s has width %d; participant %s takes %d values "
                                "there" % (of, w.width, session.p.name, width))
        if not 1 <= count <= limit:  # before anything is allocated for it
            raise ProtocolError(E.BAD_REQUEST, "%s has %d samples; 1 to %d are allowed (one per "
                                "micro step and one more)" % (of, count, limit))
        if len(w.values) != width * count:
            raise ProtocolError(E.BAD_REQUEST, "%s has %d values for %d samples of %d"
                                % (of, len(w.values), count, width))
        if not 0 <= w.degree <= 3:
            raise ProtocolError(E.BAD_REQUEST, "%s has degree %d; 0 to 3 are allowed"
                                % (of, w.degree))
        times = np.array(w.times, dtype=float)
        values = np.array(w.values, dtype=float).reshape(count, width)
        if not (np.isfinite(times).all() and np.isfinite(values).all()):
            raise ProtocolError(E.BAD_REQUEST, of + " holds a value that is not finite")
        if count > 1 and not (np.diff(times) > 0).all():
            raise ProtocolError(E.BAD_REQUEST, of + ": its sample times do not increase")
        outside = np.flatnonzero((times < t0 - slack) | (times > t1 + slack))
        if len(outside):
            s = int(outside[0])
            raise ProtocolError(E.BAD_REQUEST, "%s: sample %d at t = %.10g s lies outside the "
                                "macro step [%.10g, %.10g] s (tolerance %.10g s)"
                                % (of, s, times[s], t0, t1, slack))
        inputs = api.Inputs()
        for j, q in enumerate(i.receives):
            part = np.ascontiguousarray(values[:, j * i.n:(j + 1) * i.n])
            setattr(inputs, q, Sampled(times, part, w.degree, t0, H))
        out.append(inputs)
    return out


def ends(session, held):
    """The values of decoded waveforms at t_n and t_n+1 as two lists of
    InterfaceData, kept as ramped inputs are (Save)."""
    start, end = [], []
    for i, w in zip(session.interfaces, held):
        for side, out in (("start", start), ("end", end)):
            b = packed.encode({q: getattr(getattr(w, q), side) for q in i.receives}, i.receives)
            out.append(pb.InterfaceData.FromString(b))
    return start, end


class Recorder:
    """The samples of one macro step: the outputs at its start and wherever
    the participant records them (after each micro step)."""

    def __init__(self, session):
        self.session = session
        self.samples = []  # (t, [encoded InterfaceData])

    def begin(self, t, outputs):
        self.samples = []
        self.add(t, outputs)

    def add(self, t, outputs):
        s = self.session
        if outputs is None or len(outputs) != len(s.interfaces):
            raise ProtocolError(E.INTERNAL, "record(): outputs for %s interfaces; the "
                                "participant has %d" % ("no" if outputs is None else
                                                        len(outputs), len(s.interfaces)))
        t = float(t)
        if self.samples and not t > self.samples[-1][0]:
            if t == self.samples[-1][0]:  # the same time again: the later outputs stand
                self.samples.pop()
            else:
                raise ProtocolError(E.INTERNAL, "record(): a sample at t = %r s after one at "
                                    "%r s; times must increase" % (t, self.samples[-1][0]))
        self.samples.append((t, [packed.encode(o, i.sends)
                                 for i, o in zip(s.interfaces, outputs)]))

    def write(self, report, t_end, outputs):
        """The samples into a StepReport; the step's outputs close them at t_end."""
        # A last sample within a billionth of a step of the end is the end.
        if self.samples[-1][0] < t_end - 1e-9 * self.session.H:
            self.add(t_end, outputs)
        for t, encoded in self.samples:
            sample = report.samples.add()
            sample.t = t
            for b in encoded:
                sample.outputs.interfaces.add().MergeFromString(b)
        self.samples = []


def refusal(p):
    return ProtocolError(E.BAD_REQUEST, "participant %s takes no substep waveforms (its "
                         "class does not set takes_waveforms): run it with --inputs hold or "
                         "linear, not waveform0 to waveform3" % p.name)


class Handlers:
    """The session's part: RecordSamples, and waveforms in SetInputs and Step."""

    def on_record_samples(self, req, out):
        if self.step < 0:
            raise ProtocolError(E.OUT_OF_ORDER, "record_samples before initialize")
        on = req.record_samples.on
        if on and not self.p.takes_waveforms:
            raise refusal(self.p)
        self.p._recorder = Recorder(self) if on else None
        out.ack.SetInParent()
        return out

    def take_waveforms(self, s, with_inputs):
        """The waveforms of a SetInputs or Step `s` become the held inputs."""
        if with_inputs:
            raise ProtocolError(E.BAD_REQUEST, "macro step %d: inputs and waveforms in one "
                                "message; send one of them" % s.step)
        if not self.p.takes_waveforms:
            raise refusal(self.p)
        self.held = decode(self, s.step, s.waveforms)
        self.held_wire = ends(self, self.held)
