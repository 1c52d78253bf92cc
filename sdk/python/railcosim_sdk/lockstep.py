"""The lock step (docs/protocol.md §17, capability "lockstep"): the direct
plane's form for the couplings the master decides at every macro step
(implicit coupling, ramped and extrapolated inputs).

The master sends Window{lockstep = true}; the participant answers Ack at
once and from then on serves SetInputs, GetOutputs, Step, Save, Restore and
RecordSamples exactly as on the relayed plane (same replies, same ids, in
order). The first request of any other kind ends the lock step and is
answered as usual. The session already reads the master's connection on
the thread that steps the participant, so nothing changes hands.

What the lock step adds is the checkpoint the participant keeps itself:
Save{keep} and Restore{kept} answer Ack, and a Step may carry the same as
flags (keep_checkpoint, restore_checkpoint), done before its inputs are
set. The snapshot holds what a shipped State holds (the participant's
save(), its step and micro-step counters, its held inputs and its last
outputs), so a step taken again from it is bit for bit the step taken
again from a State that crossed the wire.
"""

import numpy as np

from .session import Session
from .wire import E, ProtocolError

# The requests a lock step serves; any other ends it.
STEP_REQUESTS = frozenset(("set_inputs", "get_outputs", "step", "save", "restore",
                           "record_samples"))


class Kept:
    """A snapshot the participant keeps: the same contents as on_save's State."""

    __slots__ = ("step", "micro_steps", "values", "held", "held_wire", "last")

    def __init__(self, session):
        s = session
        self.values = np.array(s.p.save(), dtype=float)  # a copy, as save()'s floats
        self.step, self.micro_steps = s.step, s.p.micro_steps
        self.held, self.held_wire = s.held, s.held_wire
        # The outputs as a State carries them: the quantities sent, copied
        # (a participant may go on to change its arrays in place).
        self.last = None if s.last is None else [
            {q: np.array(o[q], dtype=float) for q in i.sends}
            for i, o in zip(s.interfaces, s.last)]

    def restore(self, session, held=True):
        """Back to the snapshot; `held` False: leave the held inputs to the
        step that restores, which brings its own."""
        s = session
        # A fresh array every time: restore() may keep it and change it.
        s.p.restore(self.values.copy())
        s.step = self.step
        s.p.micro_steps = self.micro_steps
        if held and held_from(self.held) == self.step * s.H:
            s.held, s.held_wire = self.held, self.held_wire  # decoded once, read-only arrays
        elif held:  # inputs held since an earlier step: over this one, as a State brings them
            s.set_inputs(*self.held_wire)
        s.last = self.last  # the session never changes these; a step replaces them


def held_from(held):
    """The time from which held inputs (a list of api.Inputs) are defined."""
    for w in held or ():
        for q in ("displacement", "velocity", "force"):
            v = getattr(w, q)
            if v is not None:
                return v.t0
    return None


class LockstepSession(Session):
    """A session that also serves the lock step when it serves the direct
    plane (a server that offers it; not with --relayed-only)."""

    kept = None         # the snapshot kept last (Kept)
    in_lockstep = False
    ran_windows = False  # windows of the direct plane ran in this session

    def hello_reply(self, out):
        out = super().hello_reply(out)
        if self.links_hook is not None:
            out.hello_reply.capabilities.append("lockstep")
        return out

    def handle(self, req):
        if self.in_lockstep and req.WhichOneof("body") not in STEP_REQUESTS:
            self.in_lockstep = False  # answered as usual
        return super().handle(req)

    # ---- entering ----

    def on_window(self, req, out):
        if not req.window.lockstep:
            self.ran_windows = True
            return super().on_window(req, out)
        if self.step < 0:
            raise ProtocolError(E.OUT_OF_ORDER, "a lock step needs initialize first")
        if self.ran_windows:
            raise ProtocolError(E.OUT_OF_ORDER, "a lock step cannot follow windows of the "
                                "direct data plane in one session")
        if self.links_hook is None:
            raise ProtocolError(E.BAD_REQUEST, "this participant does not serve the direct "
                                "data plane (--relayed-only), so no lock step either")
        self.in_lockstep = True
        out.ack.SetInParent()
        return out

    # ---- the checkpoint it keeps ----

    def keep(self):
        self.kept = Kept(self)

    def restore_kept(self, held=True):
        if self.kept is None:
            raise ProtocolError(E.OUT_OF_ORDER, "restore of the kept checkpoint, but none was "
                                "kept (a save with keep, or a step with keep_checkpoint, comes "
                                "first)")
        self.kept.restore(self, held)

    def on_save(self, req, out):
        if not req.save.keep:
            return super().on_save(req, out)
        if self.step < 0:
            raise ProtocolError(E.OUT_OF_ORDER, "save before initialize")
        self.keep()
        out.ack.SetInParent()
        return out

    def on_restore(self, req, out):
        if not req.restore.kept:
            return super().on_restore(req, out)
        self.restore_kept()
        out.ack.SetInParent()
        return out

    def on_step(self, req, out):
        s = req.step
        if s.keep_checkpoint or s.restore_checkpoint:
            if self.step < 0:
                raise ProtocolError(E.OUT_OF_ORDER, "a step before initialize")
            # Before the inputs are set, as a Save or Restore just before.
            if s.keep_checkpoint:
                self.keep()
            if s.restore_checkpoint:
                self.restore_kept(held=not (s.HasField("inputs") or s.HasField("waveforms")))
        return super().on_step(req, out)
