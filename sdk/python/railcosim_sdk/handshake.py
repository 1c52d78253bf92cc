"""The accepting end of the peer links' handshakes (docs/protocol.md §17),
side by side: each connection that reaches the participant's port while its
links open gets HANDSHAKE_SECONDS for its hello (and its answer to the
challenge), and a silent or slow one holds up nobody else. Until a
connection has proved the shared secret and the session key, it learns
nothing of this participant or its peers."""

import hmac
import secrets
import select
import socket
import time

from .auth import auth_answer, auth_proof
from .wire import E, PROTOCOL_VERSION, Channel, LinkClosed, ProtocolError, pb

HANDSHAKE_SECONDS = 2.0  # a connection's whole handshake
MAX_HANDSHAKES = 256     # at once; a newer one closes the oldest silent one
MAX_HANDSHAKE_FRAME = 4096


class Refused(Exception):
    pass


class Incoming:
    def __init__(self, sock):
        try:
            where = "%s:%d" % sock.getpeername()[:2]
        except OSError:
            where = "an unknown address"
        self.ch = Channel(sock, "a connection from %s" % where)
        self.since = time.monotonic()
        self.id = 0
        self.hello = None  # the peer's hello, once read
        self.nonce = None  # the challenge sent (with a shared secret)

    def refuse(self, code, why):
        self.ch.send_error(self.id, code, why)
        self.ch.close()
        return Refused("%s: %s: %s" % (self.ch.what, E.Code.Name(code), why))


class Acceptor:
    """Takes connections from `inbox` and completes their handshakes until
    every link without a host (the peer connects) has its channel."""

    def __init__(self, me, name, key, token, links, inbox):
        self.me, self.name, self.key, self.token = me, name, key, token
        self.links, self.inbox = links, inbox
        self.incoming = []
        self.refused = []  # why each refused connection was, for the timeout's message

    def waiting(self):
        return [l for l in self.links if not l.host and l.chan is None]

    def poll(self, seconds):
        """One round: new connections, expired ones, frames that arrived."""
        sock = self.inbox.take(0.0 if self.incoming else seconds)
        while sock is not None:
            if len(self.incoming) >= MAX_HANDSHAKES:
                silent = [c for c in self.incoming if c.hello is None and not c.ch.buf]
                self.drop(silent[0] if silent else self.incoming[0], E.BUSY,
                          "too many connections at once; try again")
            self.incoming.append(Incoming(sock))
            sock = self.inbox.take(0.0)
        now = time.monotonic()
        for c in list(self.incoming):
            if now - c.since > HANDSHAKE_SECONDS:
                self.drop(c, E.TIMEOUT, "no complete handshake within %g s" % HANDSHAKE_SECONDS)
        if not self.incoming:
            return
        ready, _, _ = select.select([c.ch.sock for c in self.incoming], [], [], seconds)
        for c in list(self.incoming):
            if c.ch.sock not in ready and not c.ch.pending():
                continue
            try:
                if len(c.ch.buf) >= 4 and int.from_bytes(c.ch.buf[:4], "big") > \
                        MAX_HANDSHAKE_FRAME:
                    raise c.refuse(E.FRAME_TOO_LARGE, "a handshake frame is at most %d bytes"
                                   % MAX_HANDSHAKE_FRAME)
                e = c.ch.receive(0.001)
            except socket.timeout:
                continue  # part of a frame: the rest may come within its time
            except (LinkClosed, OSError, ProtocolError) as x:
                self.forget(c, x)
                continue
            except Refused as x:
                self.forget(c, x, closed=True)
                continue
            try:
                self.advance(c, e)
            except Refused as x:
                self.forget(c, x, closed=True)

    def advance(self, c, e):
        if c.hello is None:
            if not e.HasField("hello") or e.hello.role != "peer":
                raise c.refuse(E.BUSY, "this participant serves a session; it accepts nothing "
                               "but its peer links")
            c.hello, c.id = e.hello, e.id
            if self.token is not None:
                c.nonce = secrets.token_bytes(32)
                c.ch.send(pb.Envelope(id=c.id, challenge=pb.Challenge(nonce=c.nonce)))
                return
        elif not e.HasField("auth") or not hmac.compare_digest(
                e.auth.mac, auth_answer(self.token, self.me, c.nonce)):
            raise c.refuse(E.UNAUTHORIZED, "the answer to the challenge was missing or wrong")
        h = c.hello
        if not hmac.compare_digest(h.session, self.key):
            raise c.refuse(E.UNAUTHORIZED, "the session key is not this session's")
        if h.participant != self.me:
            raise c.refuse(E.WRONG_ROLE, "this program serves the %s participant, not the %s "
                           "participant" % (self.me, h.participant))
        waiting = self.waiting()
        match = [l for l in waiting if l.peer == h.peer_of]
        if not match:
            raise c.refuse(E.WRONG_ROLE, "this participant expects peer links from %s, not "
                           "from the %s participant" % (
                               ", ".join(l.peer for l in waiting) or "nobody", h.peer_of))
        reply = pb.Envelope(id=c.id, hello_reply=pb.HelloReply(
            protocol_version=PROTOCOL_VERSION, participant=self.me, name=self.name))
        if self.token is not None and h.nonce:  # this end proves the secret too
            reply.hello_reply.proof = auth_proof(self.token, self.me, h.nonce, c.nonce)
        c.ch.send(reply)
        match[0].chan = c.ch
        self.incoming.remove(c)

    def drop(self, c, code, why):
        self.forget(c, c.refuse(code, why), closed=True)

    def forget(self, c, why, closed=False):
        if not closed:
            c.ch.close()
        if c in self.incoming:
            self.incoming.remove(c)
        self.refused.append(str(why))
        del self.refused[:-8]  # the latest few, for the message

    def close(self, code, why):
        """Ends every handshake still open."""
        for c in list(self.incoming):
            c.refuse(code, why)
        self.incoming = []
