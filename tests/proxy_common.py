"""What the test proxies share: closing both ends of a forwarded
connection, and the listener that prints its address and forwards every
connection it accepts to the node behind it.

serve(upstream, pumps): for each accepted connection, pumps(first) gives
the two functions that carry client->node and node->client bytes (each
called as f(src, dst)); `first` is True for the first connection only
(the master's: the nodes' peer links come later)."""
import socket
import threading


def close_both(src, dst):
    for s in (src, dst):
        try:
            s.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass


def serve(upstream, pumps):
    host, port = upstream.rsplit(":", 1)
    listener = socket.socket()
    listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    listener.bind(("127.0.0.1", 0))
    listener.listen(16)
    print("listening on 127.0.0.1:%d" % listener.getsockname()[1], flush=True)
    first = True
    while True:
        client, _ = listener.accept()
        node = socket.create_connection((host, int(port)))
        for s in (client, node):
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        to_node, to_client = pumps(first)
        threading.Thread(target=to_node, args=(client, node), daemon=True).start()
        threading.Thread(target=to_client, args=(node, client), daemon=True).start()
        first = False
