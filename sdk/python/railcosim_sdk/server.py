"""serve(): listen, accept sessions one after another, refuse a second one
with BUSY, hand the peer links of the direct plane to the running session."""

import argparse
import queue
import socket
import sys
import threading
import tomllib
import traceback

from .auth import read_token_file
from .direct import Plane
from .lockstep import LockstepSession as Session  # the session, with the lock step
from . import participant as api
from .wire import E, Channel, LinkClosed, LinkLost, ProtocolError, pb

HELLO_SECONDS = 10.0
IDLE_SECONDS = 60.0
ENDING_SECONDS = 0.5  # how long a new connection waits for a session that is ending


class Inbox:
    """Connections that arrive while the session waits for its peer links."""

    def __init__(self):
        self.waiting = False
        self.queue = queue.Queue()
        self.lock = threading.Lock()

    def offer(self, sock):
        """Queues a new connection if the session waits for peers."""
        with self.lock:
            if self.waiting:
                self.queue.put(sock)
            return self.waiting

    def take(self, timeout):
        try:
            return self.queue.get(timeout=timeout)
        except queue.Empty:
            return None

    def stop_waiting(self):
        """No more peers: BUSY to the connections still queued."""
        with self.lock:
            self.waiting = False
        while True:
            try:
                sock = self.queue.get_nowait()
            except queue.Empty:
                return
            ch = Channel(sock, "a connection")
            ch.send_error(0, E.BUSY, "this participant serves a session; its peer links are "
                          "open")
            ch.close()


class Server:
    def __init__(self, participant, listen, token, config, name, direct=True):
        self.p, self.token, self.config, self.name = participant, token, config, name
        self.direct = direct
        host, port = listen.rsplit(":", 1)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.sock.bind((host, int(port)))
        self.sock.listen(16)
        self.sessions = queue.Queue()
        self.active = None  # the master's address while a session runs
        self.inbox = None
        self.lock = threading.Lock()
        self.ended = threading.Condition(self.lock)  # a session has ended

    def address(self):
        return "%s:%d" % self.sock.getsockname()[:2]

    def acceptor(self):
        while True:
            conn, addr = self.sock.accept()
            threading.Thread(target=self.admit, args=(conn, addr), daemon=True).start()

    def admit(self, conn, addr):
        with self.lock:
            if self.inbox is not None and self.inbox.offer(conn):
                return
            # A session that has sent its last reply is ending: a master that
            # saw that reply and connects again at once is not turned away.
            self.ended.wait_for(lambda: self.active is None, timeout=ENDING_SECONDS)
            if self.active is None:
                self.active = "%s:%d" % addr[:2]
                self.sessions.put(conn)
                return
            active = self.active
        ch = Channel(conn, "%s:%d" % addr[:2])
        ch.send_error(0, E.BUSY, "this participant already serves a session (from %s)"
                      % active)
        ch.close()

    def run(self):
        threading.Thread(target=self.acceptor, daemon=True).start()
        while True:
            conn = self.sessions.get()
            try:
                self.session(conn)
            finally:
                with self.lock:  # before the close: a master that saw it may come back
                    self.active, self.inbox = None, None
                    self.ended.notify_all()
                conn.close()

    def session(self, conn):
        master = Channel(conn, "the master at %s" % self.active)
        plane = None
        hook = None
        if self.direct:
            with self.lock:
                self.inbox = Inbox()

            def hook(session, req, out):
                nonlocal plane
                if plane is None:
                    plane = Plane(session, master, self.inbox)
                kind = req.WhichOneof("body")
                return plane.on_links(req, out) if kind == "links" else plane.on_window(req, out)
        s = Session(self.p, self.token, self.name, self.config, hook)
        s.master = master  # progress frames (progress.py) go to the master too
        req_id = 0
        try:
            while not s.closing:
                timeout = HELLO_SECONDS if s.state in ("hello", "auth") else IDLE_SECONDS
                try:
                    req = master.receive(timeout)
                except socket.timeout:
                    raise ProtocolError(E.TIMEOUT, "the master sent no complete request within "
                                        "%g s" % timeout)
                req_id = s.request_id = req.id
                master.send(s.handle(req))
                req_id = s.request_id = 0
        except LinkClosed as e:
            if e.inside_frame:
                master.send_error(0, E.BAD_FRAME, "the connection closed inside a frame",
                                  s.step, max(s.step, 0) * s.H)
        except ProtocolError as e:
            master.send_error(req_id, e.code, str(e), s.step, max(s.step, 0) * s.H, e.sender)
            print("session from %s: %s: %s" % (self.active, E.Code.Name(e.code), e),
                  file=sys.stderr, flush=True)
        except (LinkLost, socket.timeout) as e:  # the master's connection is lost
            print("session from %s: %s" % (self.active, e), file=sys.stderr, flush=True)
        except OSError as e:  # the participant's own (a file it could not write, ...)
            traceback.print_exc()
            master.send_error(req_id, E.INTERNAL, "the %s participant failed: %s: %s"
                              % (self.p.name, type(e).__name__, e), s.step,
                              max(s.step, 0) * s.H)
        except Exception as e:  # a bug in the participant must not take the server down
            traceback.print_exc()
            master.send_error(req_id, E.INTERNAL, "internal error in the %s participant: %s: %s"
                              % (self.p.name, type(e).__name__, e), s.step,
                              max(s.step, 0) * s.H)
        finally:
            if self.inbox is not None:
                self.inbox.stop_waiting()
            if plane is not None and plane.links:
                for l in plane.links:
                    if l.chan is not None:
                        l.chan.close()


def check_configure(participant, data):
    """--check-configure: the Configure the master would send (serialized,
    `data`), checked by participant.check() without building anything.
    Returns the process's exit status: 0 accepted, 2 refused (the reason
    on stderr)."""
    c = pb.Configure()
    try:
        c.ParseFromString(data)
        config = tomllib.loads(c.own_config) if c.own_config else {}
    except Exception as e:  # noqa: BLE001  (a message that is no Configure)
        print("--check-configure: standard input is not a Configure: %s" % e, file=sys.stderr)
        return 2
    participant.run = api.Run(c)
    try:
        participant.check(config, [api.Interface(i) for i in c.interfaces])
    except (api.BadInterface, api.BadRequest) as e:
        print(str(e), file=sys.stderr)
        return 2
    return 0


def serve(participant, argv=None, parents=()):
    """Serves `participant` (a Participant instance) until interrupted.

    Command line (argv, default sys.argv[1:]):
      --listen HOST:PORT   where to listen (default 127.0.0.1:0: any free port);
                           prints "listening on HOST:PORT" once it does
      --config FILE        a TOML file; its table [--table] is the config
                           configure() receives (default: the participant's
                           table of the master's scene, Configure.own_config,
                           which the master sends to an outside soil; else {})
      --table NAME         the table of --config (default: the participant's name)
      --token-file FILE    the shared secret (the master's --token-file)
      --relayed-only       do not offer the direct data plane
      --name TEXT          the name given in the hello reply (logs)
      parents:             argparse parsers (add_help=False) of the program's
                           own options, listed in --help beside these
      --check-configure    read a serialized Configure from standard input,
                           check it (participant.check) and exit: 0 if it
                           would be accepted, 2 with the reason on stderr
    """
    p = argparse.ArgumentParser(
        description="Serve the %s participant to a railcosim master, one session after "
        "another, until interrupted. Give the master the address it prints: master run "
        "--node %s=HOST:PORT." % (participant.name, participant.name),
        parents=list(parents))
    p.add_argument("--listen", default="127.0.0.1:0", metavar="HOST:PORT",
                   help="where to listen (default %(default)s: loopback, any free port); "
                   "prints 'listening on HOST:PORT' once it does. An address other than "
                   "loopback is reachable from other machines: give it --token-file too")
    p.add_argument("--config", metavar="FILE",
                   help="a TOML file whose table --table is the configuration configure() "
                   "receives (default: the participant's table of the master's scene, which "
                   "the master sends in Configure.own_config; else an empty one)")
    p.add_argument("--scene", dest="config", help=argparse.SUPPRESS)  # the example's old name
    p.add_argument("--table", default=participant.name, metavar="NAME",
                   help="the table of --config that is this participant's configuration "
                   "(default: %(default)s, the participant's name)")
    p.add_argument("--token-file", metavar="FILE",
                   help="the shared secret the master proves it knows (the master's "
                   "--token-file): a regular file only its owner may read or write (mode "
                   "0600 or 0400), at most 4,096 bytes, at least 16 characters")
    p.add_argument("--relayed-only", action="store_true",
                   help="do not offer the direct data plane (peer links between the "
                   "participants): every value goes through the master")
    p.add_argument("--name", default="%s (railcosim_sdk)" % type(participant).__name__,
                   metavar="TEXT", help="the name this participant gives in its hello reply, "
                   "for the master's logs (default: %(default)s)")
    p.add_argument("--check-configure", action="store_true",
                   help="read a serialized Configure message from standard input, check it "
                   "as a session would (participant.check), and exit: 0 if it would be "
                   "accepted, 2 with the reason on stderr")
    a = p.parse_args(argv)
    if a.check_configure:
        sys.exit(check_configure(participant, sys.stdin.buffer.read(1 << 20)))
    config = None  # the scene's table, from Configure.own_config
    if a.config:
        try:
            with open(a.config, "rb") as f:
                doc = tomllib.load(f)
        except (OSError, tomllib.TOMLDecodeError) as e:
            sys.exit("%s: %s" % (a.config, e))
        if a.table not in doc:
            sys.exit("%s: no [%s] table (the configuration of the %s participant)"
                     % (a.config, a.table, participant.name))
        config = doc[a.table]
    token = None
    if a.token_file:
        try:
            token = read_token_file(a.token_file)
        except OSError as e:
            sys.exit("--token-file: cannot read the token file %s: %s"
                     % (a.token_file, e.strerror or e))
        except ValueError as e:
            sys.exit("--token-file: %s" % e)
    try:
        server = Server(participant, a.listen, token, config, a.name, not a.relayed_only)
    except (OSError, ValueError) as e:
        sys.exit("--listen %s: %s" % (a.listen, e))
    print("listening on %s" % server.address(), flush=True)
    try:
        server.run()
    except KeyboardInterrupt:
        pass
