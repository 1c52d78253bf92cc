#!/usr/bin/env python3
"""A TCP proxy in front of a node that forwards the master's connection as
it is and, on every other connection (the peer links other nodes open to
it), rewrites one PeerData frame the node sends: the AT-th that carries
data gets a non-finite value (MODE nan), a point far in the future
(MODE jump), one value less on its first interface (MODE short), or is
replaced by bytes that are no message (MODE garbage). The node behind it
is the sender of the bad data; with DIRECTION "to", the frame rewritten is
one its peer sends it instead, and the node behind the proxy is the
receiver. MODE shift rewrites the master's connection instead: from the
AT-th step report that carries substep samples on, every sample's time is
moved 1000 s later.

  corrupt_proxy.py UPSTREAM_HOST:PORT PROTO_FILE MODE AT [from|to]

Prints "listening on 127.0.0.1:PORT", then serves until killed."""
import importlib
import os
import struct
import subprocess
import sys
import tempfile

from proxy_common import close_both, serve

proto, mode, at = sys.argv[2], sys.argv[3], int(sys.argv[4])
inbound = len(sys.argv) > 5 and sys.argv[5] == "to"
out = tempfile.mkdtemp(prefix="corrupt_proxy_")
folder, name = os.path.split(os.path.abspath(proto))
subprocess.run(["protoc", "-I", folder, "--python_out", out, name], check=True)
sys.path.insert(0, out)
pb = importlib.import_module(name.replace(".proto", "_pb2"))


def read_exact(sock, n):
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return data


def plain(src, dst):
    try:
        while True:
            data = src.recv(65536)
            if not data:
                break
            dst.sendall(data)
    except OSError:
        pass
    close_both(src, dst)


def rewriting(src, dst):
    seen = 0
    try:
        while True:
            header = read_exact(src, 4)
            if header is None:
                break
            body = read_exact(src, struct.unpack(">I", header)[0])
            if body is None:
                break
            e = pb.Envelope()
            e.ParseFromString(body)
            if mode == "shift":
                if e.WhichOneof("body") == "step_report" and len(e.step_report.samples) > 0:
                    seen += 1
                    if seen >= at:
                        for sample in e.step_report.samples:
                            sample.t += 1000.0
                        body = e.SerializeToString()
                        header = struct.pack(">I", len(body))
            elif e.WhichOneof("body") == "peer_data" and len(e.peer_data.data.interfaces) > 0:
                seen += 1
                if seen == at:
                    i = e.peer_data.data.interfaces[0]
                    values = i.displacement if len(i.displacement) else i.force
                    if mode == "nan":
                        values[0] = float("nan")
                    elif mode == "short":
                        del values[-1]
                    elif mode == "jump":
                        e.peer_data.point += 1000000000
                    body = e.SerializeToString()
                    if mode == "garbage":
                        body = b"\xff" * 8
                    header = struct.pack(">I", len(body))
            dst.sendall(header + body)
    except OSError:
        pass
    close_both(src, dst)


def pumps(first):
    """The master's connection is the first; peer links come later."""
    if mode == "shift":
        rewrite_in, rewrite_out = False, first
    else:
        rewrite_in, rewrite_out = (not first and inbound), (not first and not inbound)
    return (rewriting if rewrite_in else plain), (rewriting if rewrite_out else plain)


serve(sys.argv[1], pumps)
