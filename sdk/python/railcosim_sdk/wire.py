"""The protocol's messages and frames.

The message classes are generated from protocol/railcosim.proto by protoc
at first import, into a cache folder keyed by the schema's hash:
$RAILCOSIM_SDK_CACHE, else $XDG_CACHE_HOME/railcosim, else
~/.cache/railcosim, else TMPDIR/railcosim-EUID; a folder is used only if
it is this user's own (owner the effective uid, created 0700, no write bit
for group or others, no symbolic link; the module file too), else the
schema is compiled into a fresh private temporary folder, read and
removed (a warning names the refused folder). The schema is
$RAILCOSIM_PROTO, else protocol/railcosim.proto of the checkout this
package lives in, else (the SDK installed with the C++ package) the
railcosim.proto installed beside it. Needs Debian's protobuf-compiler and python3-protobuf.
"""

import hashlib
import os
import shutil
import socket
import stat
import struct
import subprocess
import sys
import tempfile
import time
import types

PROTOCOL_VERSION = 4
# Write deadlines: a frame to a master (a reply, a report) must be read within
# SEND_SECONDS, as the C++ node's --message-timeout; a last error within
# ERROR_SEND_SECONDS; a peer link's frames within the link's timeout.
SEND_SECONDS = 10.0
ERROR_SEND_SECONDS = 1.0
MAX_FRAME = 8 << 20


def _schema_path():
    """$RAILCOSIM_PROTO; else the checkout's protocol/railcosim.proto; else,
    for the SDK installed with the package (PREFIX/share/railcosim/sdk/python),
    the schema installed beside it (PREFIX/share/railcosim/railcosim.proto)."""
    if os.environ.get("RAILCOSIM_PROTO"):
        return os.environ["RAILCOSIM_PROTO"]
    here = os.path.dirname(os.path.abspath(__file__))
    checkout = os.path.normpath(os.path.join(here, "..", "..", "..", "protocol",
                                             "railcosim.proto"))
    installed = os.path.normpath(os.path.join(here, "..", "..", "..", "railcosim.proto"))
    return installed if not os.path.exists(checkout) and os.path.exists(installed) else checkout


def _cache_roots():
    if os.environ.get("RAILCOSIM_SDK_CACHE"):
        yield os.environ["RAILCOSIM_SDK_CACHE"]
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    yield os.path.join(base, "railcosim")
    yield os.path.join(tempfile.gettempdir(), "railcosim-%d" % os.geteuid())


def _private(path, is_dir):
    """None if `path` is this user's own (owner the effective uid, no write
    bit for group or others, no symbolic link, a folder or a regular file as
    asked); else why not. Code is imported only from such places: anyone
    else who can write the folder or the file could put code there."""
    try:
        st = os.lstat(path)
    except OSError as e:
        return "cannot be read (%s)" % (e.strerror or e)
    if stat.S_ISLNK(st.st_mode):
        return "is a symbolic link"
    if not (stat.S_ISDIR(st.st_mode) if is_dir else stat.S_ISREG(st.st_mode)):
        return "is not a %s" % ("folder" if is_dir else "regular file")
    if st.st_uid != os.geteuid():
        return "belongs to uid %d, not to this user (uid %d)" % (st.st_uid, os.geteuid())
    if st.st_mode & 0o022:
        return "can be written by others (mode %o)" % stat.S_IMODE(st.st_mode)
    return None


def _warn(text):
    print("railcosim_sdk: %s" % text, file=sys.stderr, flush=True)


def _protoc(folder, name, out):
    try:
        subprocess.run(["protoc", "-I", folder, "--python_out", out, name], check=True)
    except FileNotFoundError:
        raise SystemExit("railcosim_sdk: protoc not found; install Debian's "
                         "protobuf-compiler (scripts/install-deps.sh does)")
    for entry in os.listdir(out):  # the owner's alone, whatever the umask (002 gives 0664)
        os.chmod(os.path.join(out, entry), 0o600)


def _cached(root, key, folder, name, module):
    """The compiled schema in the private cache folder root/key, compiled
    there first if missing; None if root cannot be used (not writable, or
    not this user's own: then it warns)."""
    try:
        os.makedirs(root, mode=0o700, exist_ok=True)
    except OSError:
        return None  # not writable: the next place, silently
    why = _private(root, True)
    if why is not None:
        _warn("the cache folder %s %s; not used" % (root, why))
        return None
    target = os.path.join(root, key)
    if not os.path.lexists(target):
        try:
            work = tempfile.mkdtemp(dir=root)  # 0700, a fresh name
        except OSError:
            return None
        _protoc(folder, name, work)
        try:
            os.rename(work, target)  # atomic: another process may race us
        except OSError:
            shutil.rmtree(work, ignore_errors=True)
    path = os.path.join(target, module)
    for what, is_dir in ((target, True), (path, False)):
        why = _private(what, is_dir)
        if why is not None:
            _warn("the compiled schema's %s %s %s; not used"
                  % ("folder" if is_dir else "file", what, why))
            return None
    return path


def _read_private(path):
    """The source of `path`, opened without following a link and checked on
    the open file (owner, mode, a regular file), so that what is checked is
    what is run."""
    fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
    with os.fdopen(fd, "rb") as f:
        st = os.fstat(f.fileno())
        if (not stat.S_ISREG(st.st_mode) or st.st_uid != os.geteuid()
                or st.st_mode & 0o022 or st.st_size > MAX_FRAME):
            return None
        return f.read(MAX_FRAME + 1)


def _compiled(proto):
    """(source, path) of the schema's generated module: from a private cache
    folder (_cache_roots, the first usable), else compiled into a fresh
    private temporary folder that is removed once read."""
    with open(proto, "rb") as f:
        key = hashlib.sha256(f.read()).hexdigest()[:16]
    folder, name = os.path.split(proto)
    module = name.replace(".proto", "_pb2.py")
    for root in _cache_roots():
        path = _cached(root, key, folder, name, module)
        source = _read_private(path) if path is not None else None
        if source is not None:
            return source, path
    work = tempfile.mkdtemp(prefix="railcosim-schema-")
    try:
        _protoc(folder, name, work)
        path = os.path.join(work, module)
        source = _read_private(path)
        if source is None:
            raise SystemExit("railcosim_sdk: the schema compiled into %s cannot be read" % work)
        return source, path
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _load():
    proto = _schema_path()
    if not os.path.exists(proto):
        raise SystemExit("railcosim_sdk: the schema %s does not exist; set RAILCOSIM_PROTO "
                         "to protocol/railcosim.proto" % proto)
    source, path = _compiled(proto)
    module = types.ModuleType("railcosim_pb2")
    module.__file__ = path
    exec(compile(source, path, "exec"), module.__dict__)  # noqa: S102 (checked above)
    return module


pb = _load()
E = pb.Error  # codes: E.BAD_REQUEST, ...


class ProtocolError(Exception):
    """Ends the session with Error{code, message}."""

    def __init__(self, code, message, sender=""):
        super().__init__(message)
        self.code = code
        self.sender = sender  # PEER_FAILED: the peer whose data were refused


class SendTimeout(ProtocolError):
    """The other end did not read a frame within the channel's send deadline
    (it stopped reading): the connection is no longer usable."""

    def __init__(self, message):
        super().__init__(E.TIMEOUT, message)


class LinkLost(ConnectionError):
    """A socket error on a channel (reset, broken pipe, unreachable): the
    connection is lost. An OSError (so handlers of socket errors see it),
    told apart from the OSErrors a participant's own code raises."""


class LinkClosed(Exception):
    """The other end closed the connection (between frames, or inside one)."""

    def __init__(self, message, inside_frame=False):
        super().__init__(message)
        self.inside_frame = inside_frame


class Channel:
    """Frames over one TCP connection: 4-byte big-endian length, then an
    Envelope. Reads in large chunks and hands out every complete frame."""

    def __init__(self, sock, what, send_seconds=SEND_SECONDS):
        self.sock = sock
        self.what = what
        self.send_seconds = send_seconds  # a whole frame's write deadline
        self.buf = bytearray()
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def receive(self, timeout=None):
        """The next Envelope; raises socket.timeout, LinkClosed, ProtocolError."""
        deadline = None if timeout is None else time.monotonic() + timeout
        buf = self.buf
        while True:
            if len(buf) >= 4:
                (length,) = struct.unpack_from(">I", buf)
                if length > MAX_FRAME:
                    raise ProtocolError(E.FRAME_TOO_LARGE, "%s announced a frame of %d bytes; "
                                        "the limit is %d" % (self.what, length, MAX_FRAME))
                if len(buf) >= 4 + length:
                    env = pb.Envelope()
                    try:
                        env.ParseFromString(bytes(buf[4:4 + length]))
                    except Exception:
                        raise ProtocolError(E.BAD_FRAME, "%s sent a frame that is not an "
                                            "Envelope" % self.what)
                    del buf[:4 + length]
                    if env.WhichOneof("body") is None:
                        raise ProtocolError(E.BAD_FRAME, "%s sent an Envelope with no body"
                                            % self.what)
                    return env
            if deadline is not None:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise socket.timeout()
                self.sock.settimeout(left)
            else:
                self.sock.settimeout(None)
            try:
                chunk = self.sock.recv(1 << 16)
            except socket.timeout:
                raise
            except OSError as e:
                raise LinkLost("%s: %s" % (self.what, e.strerror or e)) from e
            if not chunk:
                raise LinkClosed("%s closed the connection" % self.what, len(buf) > 0)
            buf += chunk

    def pending(self):
        """True when a complete frame is already buffered."""
        if len(self.buf) < 4:
            return False
        return len(self.buf) >= 4 + struct.unpack_from(">I", self.buf)[0]

    def send(self, env):
        self.send_bytes(env.SerializeToString())

    def send_bytes(self, payload, seconds=None):
        """Sends one frame holding an already serialised Envelope, whole
        within `seconds` (the channel's send deadline by default); raises
        SendTimeout, after which the connection is closed."""
        seconds = self.send_seconds if seconds is None else seconds
        self.sock.settimeout(seconds)  # since Python 3.5: for the whole sendall
        try:
            self.sock.sendall(struct.pack(">I", len(payload)) + payload)
        except socket.timeout:
            self.close()  # part of the frame may have left: the stream is broken
            raise SendTimeout("%s did not read a frame of %d bytes within %g s (it stopped "
                              "reading)" % (self.what, len(payload) + 4, seconds)) from None
        except OSError as e:
            raise LinkLost("%s: %s" % (self.what, e.strerror or e)) from e

    def send_error(self, req_id, code, message, step=-1, t=0.0, sender=""):
        """Best effort, within ERROR_SEND_SECONDS: the session ends anyway."""
        e = pb.Envelope(id=req_id, error=pb.Error(code=code, message=message, step=step, t=t,
                                                  sender=sender))
        try:
            self.send_bytes(e.SerializeToString(), ERROR_SEND_SECONDS)
        except (OSError, SendTimeout):
            pass

    def close(self):
        try:
            self.sock.close()
        except OSError:
            pass
