"""One session with a master: the order of messages (docs/protocol.md §3)
and the translation between the wire and the participant's arrays."""

import hmac
import math
import secrets
import tomllib

import numpy as np

from . import packed
from . import state
from . import participant as api
from . import waveforms
from .auth import auth_answer, auth_proof  # noqa: F401  (auth_answer: the SDK's name)
from .progress import Ticker
from .wire import E, PROTOCOL_VERSION, ProtocolError, pb

STATICS_STEP = -1  # the step of a Statics request's progress frames (before the run)
_sum = np.add.reduce  # ndarray.sum without its Python wrapper


class Session(waveforms.Handlers, state.Handlers):
    """The participant's side of one session. `handle(envelope)` returns the
    reply (or raises ProtocolError); `closing` is set after Shutdown."""

    def __init__(self, participant, token, name, config=None, links_hook=None):
        self.p = participant
        self.config = config  # None: the master's own_config (else {})
        self.token, self.name = token, name
        self.state = "hello"
        self.nonce = b""
        self.closing = False
        self.step = -1
        self.H = 0.0
        self.progress_ms = 0    # Configure.progress_ms
        self.master = None      # the master's Channel, when a server runs the session
        self.request_id = 0     # the id of the request being answered
        self.interfaces = []
        self.held = None       # list of api.Inputs for the coming step
        self.held_wire = None  # (start, end) lists of InterfaceData, for Save
        self.takes = self.gives = []  # packed.Layout per interface, inputs and outputs
        self.last = None       # the outputs last returned, a list of dicts
        self.links_hook = links_hook  # (session, envelope) -> reply; the direct plane

    # ---- inputs and outputs ----

    def inputs(self, start, end=None):
        """Inputs from lists of InterfaceData (one per interface), checked."""
        if len(start) != len(self.interfaces) or (end is not None and len(end) != len(start)):
            raise ProtocolError(E.BAD_REQUEST, "inputs for %d interfaces; this participant "
                                "has %d" % (len(start), len(self.interfaces)))
        t0, H = max(self.step, 0) * self.H, self.H
        out = []
        for k, i in enumerate(self.interfaces):
            names = self.takes[k].names
            got = self.arrays(k, start[k])
            ends = None if end is None else self.arrays(k, end[k])
            w = api.Inputs()
            for j, q in enumerate(names):
                setattr(w, q, api.Waveform(got[j], None if ends is None else ends[j], t0, H))
            out.append(w)
        return out

    def arrays(self, k, idata):
        """The values of interface k's InterfaceData, checked: one array per
        quantity it receives, in the order of self.takes[k].names."""
        layout = self.takes[k]
        values = layout.view(idata.SerializeToString())
        if values is not None:  # the quantities received, n values each: are they finite?
            total = float(_sum(values, None))
            if total - total == 0.0:
                return values
        i = self.interfaces[k]  # the data differ from the usual layout: look closer
        got = packed.decode(idata)
        extra = [q for q in got if q not in i.receives]
        if extra:
            raise ProtocolError(E.BAD_REQUEST, "interface %s: %s given, but the interface "
                                "does not receive it" % (i.cut, extra[0]))
        return [self._check(got.get(q), i, q) for q in layout.names]

    @staticmethod
    def _check(a, i, q):
        n = 0 if a is None else a.shape[0]
        if n != i.n:
            raise ProtocolError(E.BAD_REQUEST, "interface %s: %d %s values, expected %d (one "
                                "per coupling point)" % (i.cut, n, q, i.n))
        total = float(_sum(a))  # not finite when a value is not (or on overflow)
        if total - total != 0.0 and not np.isfinite(a).all():
            raise ProtocolError(E.BAD_REQUEST, "interface %s: a %s value is not finite"
                                % (i.cut, q))
        return a

    def set_inputs(self, start, end=None):
        self.held = self.inputs(start, end)
        self.held_wire = (start, end)  # the messages' lists: they are not changed after

    def encode(self, outputs):
        """The participant's outputs checked and serialised, one InterfaceData
        per interface, into self.encoded."""
        if outputs is None or len(outputs) != len(self.interfaces):
            raise ProtocolError(E.INTERNAL, "the participant returned outputs for %s "
                                "interfaces; it has %d" % (
                                    "no" if outputs is None else len(outputs),
                                    len(self.interfaces)))
        for i, o in zip(self.interfaces, outputs):
            for q in i.sends:
                if len(o[q]) != i.n:
                    raise ProtocolError(E.INTERNAL, "interface %s: the participant sent %d %s "
                                        "values, expected %d" % (i.cut, len(o[q]), q, i.n))
        self.encoded = [g.encode(o) for g, o in zip(self.gives, outputs)]

    def coupling(self, outputs, data):
        """Writes the participant's outputs into a CouplingData."""
        self.encode(outputs)
        data.MergeFromString(b"".join([packed.field(1, b) for b in self.encoded]))
        return data

    def finite(self, outputs, peak, hist):
        """True when the peak, the history values and every value sent are
        finite (one sum over each interface's encoded outputs, a closer look
        only when a sum is not finite)."""
        total = peak + sum(hist)
        for g, b in zip(self.gives, self.encoded):
            values = g.view(b)
            if values is not None:
                total += float(_sum(values, None))
            elif g.names:  # arrays of another shape than n values: look at each
                total = math.nan
        if total - total == 0.0:
            return True
        return math.isfinite(peak) and all(math.isfinite(h) for h in hist) and all(
            bool(np.isfinite(o[q]).all()) for i, o in zip(self.interfaces, outputs)
            for q in i.sends)

    def summary(self, outputs):
        """What a StepReport says of the participant's outputs, checked: they
        are encoded (self.encoded); returns (history values, peak, finite)."""
        self.last = outputs
        self.encode(outputs)
        hist = [float(h) for h in self.p.history_values()]
        if len(hist) != len(self.p.history):
            raise ProtocolError(E.INTERNAL, "history_values() gave %d values for %d declared "
                                "channels" % (len(hist), len(self.p.history)))
        peak = self.p.max_abs_displacement()
        if peak is None:
            peak = 0.0
            for o in outputs:
                d = o.get("displacement")
                if d is not None and len(d):
                    m = float(np.abs(d).max())
                    if not m <= peak:  # NaN too
                        peak = m
        return hist, peak, self.finite(outputs, peak, hist)

    def report(self, outputs, step, r=None):
        """Fills a StepReport (a new one, or r) from the participant's outputs."""
        hist, peak, finite = self.summary(outputs)
        if r is None:
            r = pb.StepReport()
        r.step = step
        r.t = step * self.H
        r.outputs.MergeFromString(b"".join([packed.field(1, b) for b in self.encoded]))
        r.history.extend(hist)
        r.max_abs_displacement = peak
        r.finite = finite
        return r

    def stepped(self, n):
        """Macro step n with the held inputs: the participant's outputs."""
        try:
            if self.progress_ms > 0:  # progress frames may be due while it works
                with Ticker(self, n):
                    outputs = self.p.advance(n * self.H, self.H, self.held)
            else:
                outputs = self.p.advance(n * self.H, self.H, self.held)
        except api.StepFailed as e:
            raise ProtocolError(E.STEP_FAILED, str(e) or "the integrator gave up")
        self.step = n + 1
        return outputs

    def advance(self, n, r=None):
        """Macro step n with the held inputs; fills its StepReport (new or r)."""
        rec = self.p._recorder
        if rec is not None:  # substep waveforms: the outputs at the step's start first
            rec.begin(n * self.H, self.current_outputs())
        r = self.report(self.stepped(n), self.step, r)
        if rec is not None:
            rec.write(r, self.step * self.H, self.last)
        return r

    def advance_bytes(self, n):
        """Macro step n as advance(), its StepReport serialised: returns
        (the report's bytes, finite, max_abs_displacement)."""
        if self.p._recorder is not None:  # with samples: as a message
            r = self.advance(n)
            return r.SerializeToString(), r.finite, r.max_abs_displacement
        hist, peak, finite = self.summary(self.stepped(n))
        return (packed.step_report(self.step, self.step * self.H, self.encoded, peak, finite,
                                   hist), finite, peak)

    def current_outputs(self):
        o = self.p.outputs(self.held)
        return self.last if o is None else o

    # ---- the messages ----

    def handle(self, req):
        try:
            return self.dispatch(req)
        except api.BadRequest as e:
            raise ProtocolError(E.BAD_REQUEST, str(e))
        except api.BadInterface as e:
            raise ProtocolError(E.BAD_INTERFACE, "participant %s: %s" % (self.p.name, e))

    def dispatch(self, req):
        kind = req.WhichOneof("body")
        out = pb.Envelope(id=req.id)
        if kind == "shutdown" and self.state != "auth":
            out.ack.SetInParent()
            self.closing = True
            return out
        if self.state == "hello":
            return self.hello(req, kind, out)
        if self.state == "auth":
            return self.auth(req, kind, out)
        if self.state == "configure":
            if kind != "configure":
                raise ProtocolError(E.OUT_OF_ORDER, "expected configure, got %s" % kind)
            return self.configure(req.configure, out)
        handler = getattr(self, "on_" + str(kind), None)
        if handler is None:
            raise ProtocolError(E.BAD_REQUEST, "this participant does not accept %s messages "
                                "here" % kind)
        return handler(req, out)

    def hello(self, req, kind, out):
        if kind != "hello":
            raise ProtocolError(E.OUT_OF_ORDER, "expected hello, got %s" % kind)
        h = req.hello
        if h.protocol_version != PROTOCOL_VERSION:
            raise ProtocolError(E.VERSION_MISMATCH, "this participant speaks protocol version "
                                "%d, the hello version %d" % (PROTOCOL_VERSION,
                                                              h.protocol_version))
        self.asked = pb.Hello()
        self.asked.CopyFrom(h)
        # Before a participant with a secret has its answer, it says nothing
        # but the challenge: not whom it serves.
        if self.token is not None:
            self.nonce = secrets.token_bytes(32)
            self.state = "auth"
            out.challenge.nonce = self.nonce
            return out
        self.check_target(h)
        self.state = "configure"
        return self.hello_reply(out)

    def check_target(self, h):
        if h.role == "peer":
            raise ProtocolError(E.WRONG_ROLE, "a peer link for the %s participant, but this "
                                "one expects no peer links now" % (h.participant or "unnamed"))
        if h.participant != self.p.name:
            raise ProtocolError(E.WRONG_ROLE, "this program serves the %s participant, not the "
                                "%s participant" % (self.p.name, h.participant or "unnamed"))

    def auth(self, req, kind, out):
        nonce, self.nonce = self.nonce, b""
        h = self.asked
        if kind != "auth" or not hmac.compare_digest(
                req.auth.mac, auth_answer(self.token, h.participant, nonce)):
            raise ProtocolError(E.UNAUTHORIZED, "this participant requires the shared secret "
                                "of its --token-file; the answer to its challenge was missing "
                                "or wrong")
        self.check_target(h)
        self.state = "configure"
        self.hello_reply(out)
        # The other half: this participant proves it holds the secret too.
        if h.nonce:
            out.hello_reply.proof = auth_proof(self.token, self.p.name, h.nonce, nonce)
        return out

    def hello_reply(self, out):
        r = out.hello_reply
        r.protocol_version = PROTOCOL_VERSION
        r.participant = self.p.name
        r.name = self.name
        if self.links_hook is not None:
            r.capabilities.append("direct")
        return out

    def configure(self, c, out):
        if c.participant != self.p.name:
            raise ProtocolError(E.WRONG_ROLE, "configure names the %s participant; this "
                                "session serves the %s participant" % (c.participant,
                                                                       self.p.name))
        if not c.macro_step > 0:
            raise ProtocolError(E.BAD_REQUEST, "configure: macro_step must be > 0")
        self.interfaces = [api.Interface(i) for i in c.interfaces]
        # The layout of each interface's data in each direction (packed.Layout).
        self.takes = [packed.Layout(i.receives, i.n) for i in self.interfaces]
        self.gives = [packed.Layout(i.sends, i.n) for i in self.interfaces]
        self.H = c.macro_step
        self.progress_ms = c.progress_ms  # > 0: progress frames while a step works
        self.p.run = api.Run(c)
        self.p._recorder = None  # recording is asked for anew in each session
        config = self.config
        if config is None:  # no --config: the scene's own table for this participant
            try:
                config = tomllib.loads(c.own_config) if c.own_config else {}
            except tomllib.TOMLDecodeError as e:
                raise ProtocolError(E.BAD_REQUEST, "configure: own_config is not TOML: %s" % e)
        try:
            self.p.configure(config, self.interfaces)
        except api.BadInterface as e:
            raise ProtocolError(E.BAD_INTERFACE, "participant %s: %s" % (self.p.name, e))
        except api.BadRequest as e:
            raise ProtocolError(E.BAD_REQUEST, "configure: %s" % e)
        self.state = "ready"
        out.configured.history.extend(self.p.history)
        out.configured.results.extend(self.p.results_fields)
        return out

    def on_statics(self, req, out):
        if self.step >= 0:
            raise ProtocolError(E.OUT_OF_ORDER, "statics after initialize")
        inputs = self.inputs(req.statics.inputs.interfaces)
        # A static solve may outlast the master's reply limit: progress
        # frames (step -1) of static_iterations while it works.
        with Ticker(self, STATICS_STEP, "static_iterations"):
            outputs = self.p.statics(inputs)
        out.outputs.SetInParent()
        self.coupling(outputs, out.outputs.data)
        return out

    def on_initialize(self, req, out):
        if self.step >= 0:
            raise ProtocolError(E.OUT_OF_ORDER, "a second initialize")
        self.step = 0
        self.set_inputs(req.initialize.inputs.interfaces)
        self.report(self.p.initialize(self.held), 0, out.step_report)
        return out

    def check_step(self, n, what):
        if self.step < 0:
            raise ProtocolError(E.OUT_OF_ORDER, "%s before initialize" % what)
        if n != self.step:
            raise ProtocolError(E.OUT_OF_ORDER, "%s for macro step %d; the participant is at "
                                "macro step %d" % (what, n, self.step))

    def on_set_inputs(self, req, out):
        s = req.set_inputs
        self.check_step(s.step, "inputs")
        if s.HasField("waveforms"):
            self.take_waveforms(s, s.HasField("inputs") or s.HasField("inputs_end"))
        else:
            self.set_inputs(s.inputs.interfaces,
                            s.inputs_end.interfaces if s.HasField("inputs_end") else None)
        out.ack.SetInParent()
        return out

    def on_step(self, req, out):
        s = req.step
        self.check_step(s.step, "a step")
        if s.h != self.H:
            raise ProtocolError(E.BAD_REQUEST, "step with h = %r; the configured macro step is "
                                "%r" % (s.h, self.H))
        if s.HasField("waveforms"):
            self.take_waveforms(s, s.HasField("inputs") or s.HasField("inputs_end"))
        elif s.HasField("inputs"):
            self.set_inputs(s.inputs.interfaces,
                            s.inputs_end.interfaces if s.HasField("inputs_end") else None)
        elif s.HasField("inputs_end"):
            raise ProtocolError(E.BAD_REQUEST, "inputs_end without inputs")
        self.advance(s.step, out.step_report)
        return out

    def on_get_outputs(self, req, out):
        if self.step < 0:
            raise ProtocolError(E.OUT_OF_ORDER, "get_outputs before initialize")
        out.outputs.step = self.step
        out.outputs.t = self.step * self.H
        self.coupling(self.current_outputs(), out.outputs.data)
        return out

    def out_of_order(self, req, out):
        raise ProtocolError(E.OUT_OF_ORDER, "%s is allowed once, at the start of a session"
                            % req.WhichOneof("body"))

    on_hello = on_auth = on_configure = out_of_order

    def on_links(self, req, out):
        if self.links_hook is None:
            raise ProtocolError(E.BAD_REQUEST, "this participant does not serve the direct "
                                "data plane")
        return self.links_hook(self, req, out)

    on_window = on_links
