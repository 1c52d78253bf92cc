#!/usr/bin/env python3
"""A TCP proxy in front of a node that, on the first connection it forwards
(the master's), passes the node's bytes through for DELAY seconds and then
only one byte every 0.5 s: a node that trickles its report stream. Every
other connection (peer links) is forwarded as it is.

  trickle_proxy.py UPSTREAM_HOST:PORT DELAY

Prints "listening on 127.0.0.1:PORT", then serves until killed."""
import socket
import sys
import time

from proxy_common import close_both, serve

delay = float(sys.argv[2])


def pump(src, dst, trickle_after=None):
    start = time.monotonic()
    pending = b""
    try:
        while True:
            if trickle_after is not None and time.monotonic() - start > trickle_after:
                if not pending:
                    src.settimeout(0.5)
                    try:
                        data = src.recv(65536)
                    except socket.timeout:
                        data = b"\0"  # nothing to drip: drip a byte that is not a frame
                    if not data:
                        break
                    pending += data
                dst.sendall(pending[:1])
                pending = pending[1:]
                time.sleep(0.5)
                continue
            src.settimeout(0.05)
            try:
                data = src.recv(65536)
            except socket.timeout:
                continue
            if not data:
                break
            dst.sendall(data)
    except OSError:
        pass
    close_both(src, dst)


def pumps(first):
    """The node's bytes to the master (the first connection) trickle."""
    return (pump, lambda src, dst: pump(src, dst, delay if first else None))


serve(sys.argv[1], pumps)
