#!/usr/bin/env python3
"""A TCP proxy in front of a node that, on the first connection it forwards
(the master's), passes the node's bytes through for DELAY seconds and then
only one byte every 0.5 s: a node that trickles its report stream. Every
other connection (peer links) is forwarded as it is.

  trickle_proxy.py UPSTREAM_HOST:PORT DELAY

Prints "listening on 127.0.0.1:PORT", then serves until killed."""
import socket
import sys
import threading
import time

host, port = sys.argv[1].rsplit(":", 1)
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
    for s in (src, dst):
        try:
            s.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass


listener = socket.socket()
listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
listener.bind(("127.0.0.1", 0))
listener.listen(16)
print("listening on 127.0.0.1:%d" % listener.getsockname()[1], flush=True)
first = True
while True:
    client, _ = listener.accept()
    upstream = socket.create_connection((host, int(port)))
    for s in (client, upstream):
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    threading.Thread(target=pump, args=(client, upstream), daemon=True).start()
    threading.Thread(target=pump, args=(upstream, client, delay if first else None),
                     daemon=True).start()
    first = False
