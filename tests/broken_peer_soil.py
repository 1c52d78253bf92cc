#!/usr/bin/env python3
"""The example soil on the Python SDK, broken on purpose for the conformance
kit's own test: it takes any peer link that reaches its port, whatever its
session key and whichever participant it comes from (a correct participant
refuses both, docs/protocol.md §17).

  broken_peer_soil.py SOURCE_DIR [serve() options]"""
import os
import runpy
import sys

src = sys.argv.pop(1)
sys.path.insert(0, os.path.join(src, "sdk", "python"))
from railcosim_sdk import direct  # noqa: E402
from railcosim_sdk.wire import Channel, pb, PROTOCOL_VERSION  # noqa: E402


def accept_anyone(self, sock, deadline):
    ch = Channel(sock, "a connection")
    e = ch.receive(1.0)
    waiting = [l for l in self.links if not l.host and l.chan is None]
    ch.send(pb.Envelope(id=e.id, hello_reply=pb.HelloReply(
        protocol_version=PROTOCOL_VERSION, participant=self.s.p.name, name="broken")))
    waiting[0].chan = ch


direct.Plane.accept = accept_anyone
example = runpy.run_path(os.path.join(src, "examples", "python_soil", "soil_participant.py"))
example["rc"].serve(example["LumpedSoil"]())
