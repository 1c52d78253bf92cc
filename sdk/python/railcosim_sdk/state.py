"""The participant's state as the master asks for it: Save and Restore on
the relayed plane (its checkpoint as a State of doubles, the session's step
and micro-step counters, its held inputs and its last outputs with it;
docs/protocol.md), and GetResults after the last step."""

import numpy as np

from .wire import E, ProtocolError, pb


class Handlers:
    """The session's part: Save, Restore and GetResults."""

    def on_get_results(self, req, out):
        r = out.results
        fields = list(self.p.results())
        if len(fields) != len(self.p.results_fields):
            raise ProtocolError(E.INTERNAL, "results() gave %d fields for %d declared"
                                % (len(fields), len(self.p.results_fields)))
        for f in fields:
            r.fields.add().values.extend(np.asarray(f, dtype=float).tolist())
        r.micro_steps = int(self.p.micro_steps)
        return out

    def on_save(self, req, out):
        if self.step < 0:
            raise ProtocolError(E.OUT_OF_ORDER, "save before initialize")
        mine = [float(x) for x in self.p.save()]
        start, end = self.held_wire
        held = pb.CouplingData(interfaces=start).SerializeToString()
        ramp = b"" if end is None else pb.CouplingData(interfaces=end).SerializeToString()
        last = self.coupling(self.last, pb.CouplingData()).SerializeToString()
        blob = b"".join((held, ramp, last))
        out.state.values.extend([float(self.step), float(self.p.micro_steps), float(len(mine)),
                                 float(len(held)), float(len(ramp)), float(len(last))] + mine
                                + list(blob))
        return out

    def on_restore(self, req, out):
        v = np.array(req.restore.state.values, dtype=float)
        bad = ProtocolError(E.BAD_REQUEST, "restore: the state does not fit this participant "
                            "(it was not saved by it in this session)")
        if len(v) < 6 or not np.isfinite(v[:6]).all() or (v[:6] < 0).any() \
                or (v[:6] != np.floor(v[:6])).any():
            raise bad
        step, micro, n, a, b, c = (int(x) for x in v[:6])
        if len(v) != 6 + n + a + b + c or step > 2**53:
            raise bad
        blob = bytes(int(x) & 0xFF for x in v[6 + n:])
        try:
            held = pb.CouplingData.FromString(blob[:a]).interfaces
            ramp = pb.CouplingData.FromString(blob[a:a + b]).interfaces if b else None
            last = pb.CouplingData.FromString(blob[a + b:]).interfaces
        except Exception:
            raise bad
        self.p.restore(v[6:6 + n])
        self.step = step
        self.p.micro_steps = micro
        self.set_inputs(held, ramp)
        self.last = [{q: np.array(getattr(d, q)) for q in i.sends}
                     for i, d in zip(self.interfaces, last)]
        out.ack.SetInParent()
        return out
