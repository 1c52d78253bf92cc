"""The direct data plane (docs/protocol.md §17): Links, peer links, and the
Window the participant runs on its own, streaming its reports."""

import secrets
import select
import socket
import time

import numpy as np

from . import packed
from . import participant as api
from .handshake import Acceptor
from .auth import auth_answer, proof_failure
from .wire import E, PROTOCOL_VERSION, Channel, LinkClosed, ProtocolError, SendTimeout, pb

_sum = np.add.reduce  # ndarray.sum without its Python wrapper


class Unchecked(list):
    """A peer's decoded data whose values check() did not test for being
    finite (its last data, which a diverging peer may send)."""


class Link:
    def __init__(self, wire):
        self.peer = wire.peer
        self.host, self.port = wire.host, wire.port
        self.interfaces = list(wire.interfaces)
        self.ahead, self.refreshes = wire.ahead, wire.refreshes
        self.chan = None
        self.have, self.data = -1, None          # point and InterfaceData list
        self.fresh_have, self.fresh = -1, None   # the second sending (refresh)
        self.arrays = self.fresh_arrays = None   # the same decoded, {quantity: array} each


class Plane:
    """The direct plane of one session. `inbox` is the server's queue of
    connections that arrive while this session waits for its peers."""

    def __init__(self, session, master, inbox):
        self.s, self.master, self.inbox = session, master, inbox
        self.links = None
        self.opened = False
        self.sent = -1
        self.sent_last = False

    # ---- Links ----

    def on_links(self, req, out):
        s = self.s
        if s.step != 0 or self.links is not None:
            raise ProtocolError(E.OUT_OF_ORDER, "links are set once, after initialize and "
                                "before the first step")
        w = req.links
        bad = lambda why: ProtocolError(E.BAD_REQUEST, "links for the %s participant: %s"
                                        % (s.p.name, why))
        if len(w.session) < 16:
            raise bad("the session key must have at least 16 bytes")
        self.key, self.refresh = w.session, w.refresh
        self.timeout = (w.timeout_ms or 10000) / 1000.0
        links = [Link(l) for l in w.links]
        covered = [0] * len(s.interfaces)
        for l in links:
            if not l.peer or l.peer == s.p.name:
                raise bad("a link names no other participant")
            if l.host and not 0 < l.port < 65536:
                raise bad("the link to %s has no port" % l.peer)
            if not l.interfaces:
                raise bad("the link to %s carries no interface" % l.peer)
            for i in l.interfaces:
                if not 0 <= i < len(covered):
                    raise bad("interface %d does not exist" % i)
                covered[i] += 1
        if len({l.peer for l in links}) != len(links):
            raise bad("two links to the same participant")
        for i, c in enumerate(covered):
            if c != 1:
                raise bad("interface %d faces %d links instead of one" % (i, c))
        self.links = links
        self.inbox.waiting = any(not l.host for l in links)
        out.ack.SetInParent()
        return out

    # ---- opening the links ----

    def open(self):
        deadline = time.monotonic() + self.timeout
        acceptor = Acceptor(self.s.p.name, self.s.name, self.key, self.s.token, self.links,
                            self.inbox)
        try:
            for l in self.links:
                if l.host:
                    l.chan = self.connect(l, deadline)
            while any(l.chan is None for l in self.links):
                if self.master_gone():
                    acceptor.close(E.BUSY, "this participant is ending a session; connect again")
                    raise ProtocolError(E.PEER_FAILED, "the master ended the session while the "
                                        "peer links were opening")
                if time.monotonic() >= deadline:
                    acceptor.close(E.TIMEOUT, "the links' time is up")
                    missing = ", ".join(l.peer for l in self.links if l.chan is None)
                    raise ProtocolError(E.TIMEOUT, "the peer link(s) from %s did not open within "
                                        "%d ms%s" % (missing, self.timeout * 1000, (
                                            " (refused meanwhile: %s)" % "; ".join(
                                                acceptor.refused)) if acceptor.refused else ""))
                acceptor.poll(min(0.05, max(deadline - time.monotonic(), 0.001)))
        finally:
            self.inbox.stop_waiting()
        for l in self.links:
            l.chan.what = "the %s participant" % l.peer
            l.chan.send_seconds = self.timeout  # a peer that stops reading: PEER_FAILED
        self.opened = True

    def connect(self, l, deadline):
        who = "the %s participant at %s:%d" % (l.peer, l.host, l.port)
        while True:  # the peer may not listen yet: retry until the deadline
            try:
                sock = socket.create_connection((l.host, l.port),
                                                max(deadline - time.monotonic(), 0.001))
                break
            except OSError as e:
                if time.monotonic() + 0.05 >= deadline:
                    raise ProtocolError(E.TIMEOUT, "peer link to %s: %s" % (who, e))
                time.sleep(0.05)
        try:
            return self.handshake(l, Channel(sock, who), who, deadline)
        except (socket.timeout, LinkClosed, OSError) as e:
            raise ProtocolError(E.PEER_FAILED, "peer link to %s: %s" % (
                who, str(e) or "no answer to the hello in time"))

    def handshake(self, l, ch, who, deadline):
        token = self.s.token
        mine = secrets.token_bytes(32) if token is not None else b""
        ch.send(pb.Envelope(hello=pb.Hello(protocol_version=PROTOCOL_VERSION, role="peer",
                                           participant=l.peer, peer_of=self.s.p.name,
                                           session=self.key, name=self.s.name, nonce=mine)))
        left = lambda: max(deadline - time.monotonic(), 0.001)
        reply = ch.receive(left())
        challenge = reply.challenge.nonce if reply.HasField("challenge") else None
        if reply.HasField("challenge"):
            if self.s.token is None:
                raise ProtocolError(E.UNAUTHORIZED, "peer link to %s: that participant requires "
                                    "a shared secret; start this one with the same "
                                    "--token-file" % who)
            ch.send(pb.Envelope(auth=pb.Auth(mac=auth_answer(self.s.token, l.peer,
                                                             reply.challenge.nonce))))
            reply = ch.receive(left())
        if reply.HasField("error"):
            raise ProtocolError(reply.error.code, "peer link to %s refused: %s: %s" % (
                who, E.Code.Name(reply.error.code), reply.error.message))
        if not reply.HasField("hello_reply") or reply.hello_reply.participant != l.peer:
            raise ProtocolError(E.WRONG_ROLE, "peer link to %s: the program there does not "
                                "serve %s" % (who, l.peer))
        why = token is not None and proof_failure(token, l.peer, mine, challenge,
                                                  reply.hello_reply.proof)
        if why:
            raise ProtocolError(E.UNAUTHORIZED, "peer link to %s: %s" % (who, why))
        return ch

    def master_gone(self):
        """True when the master's connection has closed (it sends nothing
        during a window, so anything readable is its end)."""
        if self.master.pending():
            return False
        try:
            r, _, _ = select.select([self.master.sock], [], [], 0)
            return bool(r) and self.master.sock.recv(1, socket.MSG_PEEK) == b""
        except OSError:
            return True

    # ---- the window ----

    def send_outputs(self, encoded, last, refresh):
        """Sends the outputs at self.point (encoded InterfaceData, one per
        interface) to every peer, each its link's interfaces."""
        for l in self.links:
            try:
                l.chan.send_bytes(packed.peer_data(self.point, [encoded[i] for i in l.interfaces],
                                                   last, refresh))
            except SendTimeout as e:
                raise ProtocolError(E.PEER_FAILED, "%s at macro step %d (t = %g s)" % (
                    e, self.point, self.point * self.s.H), sender=l.peer)
        if not refresh:
            self.sent = self.point
        self.sent_last = self.sent_last or last

    def send_stop(self):
        if self.sent_last:
            return
        self.sent_last = True
        for l in self.links:
            try:
                l.chan.send_bytes(pb.Envelope(peer_data=pb.PeerData(
                    point=self.point, last=True)).SerializeToString(), 1.0)
            except (OSError, SendTimeout):
                pass

    def begin(self, req_id):
        """The window's reports go to the master in frames of the request's id."""
        self.id, self.pending, self.last_flush = req_id, [], time.monotonic()

    def flush(self, waiting_for=""):
        """Sends the reports not sent yet (serialised StepReports), and the
        peer this participant waits for."""
        if not self.pending and not waiting_for:
            return
        self.master.send_bytes(packed.reports(self.id, self.pending, waiting_for))
        self.pending = []
        self.last_flush = time.monotonic()

    def await_link(self, l, need, fresh):
        while (l.fresh_have if fresh else l.have) < need:
            if self.end < need:
                return False
            waited = 0.0
            while True:
                patience = min(0.05, self.timeout)
                try:
                    e = l.chan.receive(patience)
                    break
                except socket.timeout:
                    waited += patience
                    if waited >= self.timeout:
                        raise ProtocolError(E.PEER_FAILED, "%s sent nothing for %d ms" % (
                            l.chan.what, self.timeout * 1000))
                    if waited == patience:
                        self.flush(l.peer)
                    if self.master_gone():
                        raise ProtocolError(E.PEER_FAILED, "the master closed the session while "
                                            "this participant waited for %s" % l.chan.what)
                except (LinkClosed, OSError) as x:
                    raise ProtocolError(E.PEER_FAILED, "the peer link to %s: %s" % (
                        l.chan.what, x))
            if not e.HasField("peer_data"):
                raise self.refused(l, "%s on its peer link" % e.WhichOneof("body"))
            d = e.peer_data
            arrays = self.check(l, d)
            if d.last and d.point < self.end:
                self.end = d.point
                self.why = "%s stops at macro step %d" % (l.chan.what, d.point)
            if not len(d.data.interfaces):
                continue
            if d.refresh:
                l.fresh, l.fresh_arrays, l.fresh_have = d.data.interfaces, arrays, d.point
            else:
                l.data, l.arrays, l.have = d.data.interfaces, arrays, d.point
        return True

    def refused(self, l, what):
        return ProtocolError(E.PEER_FAILED, "%s sent %s at macro step %d (t = %g s)" % (
            l.chan.what, what, self.point, self.point * self.s.H), sender=l.peer)

    def check(self, l, d):
        """Every number from a peer is checked before it is used: points go up
        by one (the second sending after the first), a stop marker comes at
        the last point sent or the next, the link's interfaces, finite values
        (but in a diverging peer's last data). Returns the data decoded: one
        {quantity: array} per interface (None for a stop marker)."""
        p, data = d.point, len(d.data.interfaces) > 0
        if not data and d.last:
            if p < l.have or p > l.have + 1:
                raise self.refused(l, "a stop marker for point %d, its data being at point %d"
                                   % (p, l.have))
        elif not data:
            raise self.refused(l, "peer data for point %d with no values and no stop" % p)
        elif d.refresh:
            if not l.refreshes:
                raise self.refused(l, "a second sending (refresh) on a link whose peer sends "
                                   "once per step")
            if p != l.fresh_have + 1 or p > l.have:
                raise self.refused(l, "a second sending for point %d where point %d was due"
                                   % (p, l.fresh_have + 1))
        elif p != l.have + 1:
            raise self.refused(l, "data for point %d where point %d was due" % (p, l.have + 1))
        if not data:
            return None
        if len(d.data.interfaces) != len(l.interfaces):
            raise self.refused(l, "%d interfaces on a link of %d" % (
                len(d.data.interfaces), len(l.interfaces)))
        # Each interface's data as the one array of its usual layout, else
        # {quantity: array}, which hold() checks against the interface.
        takes = self.s.takes
        arrays = []
        for k, idata in zip(l.interfaces, d.data.interfaces):
            values = takes[k].view(idata.SerializeToString())
            arrays.append(packed.decode(idata) if values is None else values)
        if d.last:  # a diverging peer's last data: hold() checks it before any use
            return Unchecked(arrays)
        total = 0.0  # not finite when a value is not (or on overflow): look closer
        for got in arrays:
            if isinstance(got, dict):
                for a in got.values():
                    total += float(_sum(a))
            else:
                total += float(_sum(got, None))
        if total - total != 0.0 and not all(
                np.isfinite(a).all() for got in arrays
                for a in (got.values() if isinstance(got, dict) else (got,))):
            raise self.refused(l, "a non-finite value for point %d" % p)
        return arrays

    def hold(self, fresh):
        """Holds the links' data over the step as the session's inputs
        (Session.set_inputs with the arrays check() decoded)."""
        s = self.s
        held, data = [None] * len(s.interfaces), [None] * len(s.interfaces)
        t0, H = s.step * s.H, s.H
        for l in self.links:
            src, got = (l.fresh, l.fresh_arrays) if fresh and l.refreshes else (l.data, l.arrays)
            ok = not isinstance(got, Unchecked)  # check() found every value finite
            for k, i in enumerate(l.interfaces):
                data[i] = src[k]
                held[i] = self.inputs(i, got[k], ok, t0, H)
        s.held, s.held_wire = held, (data, None)

    def inputs(self, k, got, ok, t0, H):
        """The api.Inputs of interface k from what check() decoded of it (ok:
        its values were found finite), held over [t0, t0 + H]."""
        s = self.s
        names, w = s.takes[k].names, api.Inputs()
        if not isinstance(got, dict):  # the usual layout: counted; finite when ok
            if ok:
                for j, q in enumerate(names):
                    setattr(w, q, api.Waveform(got[j], None, t0, H))
                return w
            got = dict(zip(names, got))
        i = s.interfaces[k]
        extra = [q for q in got if q not in i.receives]
        if extra:
            raise ProtocolError(E.BAD_REQUEST, "interface %s: %s given, but the interface "
                                "does not receive it" % (i.cut, extra[0]))
        for q in i.receives:
            a = got.get(q)
            if not ok or a is None or a.shape[0] != i.n:
                a = s._check(a, i, q)  # the count (and finiteness) refused, naming it
            setattr(w, q, api.Waveform(a, None, t0, H))
        return w

    def on_window(self, req, out):
        s, w = self.s, req.window
        if self.links is None:
            raise ProtocolError(E.OUT_OF_ORDER, "a window needs links first")
        if not self.opened:
            self.open()
            self.point = s.step
            for l in self.links:  # every link's data starts at the current point
                l.have = l.fresh_have = s.step - 1
        if w.first_step != s.step:
            raise ProtocolError(E.OUT_OF_ORDER, "window from macro step %d, but this "
                                "participant is at %d" % (w.first_step, s.step))
        if w.end_step <= w.first_step:
            raise ProtocolError(E.BAD_REQUEST, "a window must hold at least one macro step")
        self.end, self.why = w.end_step, ""
        self.begin(req.id)
        every = w.report_steps or 64
        try:
            self.run(w.divergence_bound, every)
        except Exception:  # the peers stop too; the master gets the reports, then the error
            self.send_stop()
            self.flush()
            raise
        if self.point < w.end_step:
            self.send_stop()
        self.flush()
        out.window_done.step = self.point
        if self.point < w.end_step:
            out.window_done.reason = self.why
        return out

    def run(self, bound, every):
        s = self.s
        if self.sent < self.point:
            s.coupling(s.last, pb.CouplingData())
            self.send_outputs(s.encoded, False, False)
        while self.point < self.end:
            n = self.point
            if not all([self.await_link(l, n + (1 if l.ahead else 0), False)
                        for l in self.links]) or n >= self.end:
                break
            self.hold(False)
            if self.refresh:
                s.coupling(s.current_outputs(), pb.CouplingData())
                self.send_outputs(s.encoded, False, True)
            again = [l for l in self.links if l.refreshes]
            if again:
                if not all([self.await_link(l, n, True) for l in again]):
                    break
                self.hold(True)
            report, finite, peak = s.advance_bytes(n)  # a step that fails has no report
            self.pending.append(report)
            self.point = n + 1
            diverged = bound > 0 and (not finite or peak > bound)
            if diverged:
                self.end = self.point
                self.why = "diverged at macro step %d" % self.point
            self.send_outputs(s.encoded, diverged, False)
            if len(self.pending) >= every or time.monotonic() - self.last_flush >= 0.02:
                self.flush()
