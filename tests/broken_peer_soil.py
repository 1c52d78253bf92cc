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
from railcosim_sdk import handshake  # noqa: E402
from railcosim_sdk.wire import pb, PROTOCOL_VERSION  # noqa: E402


def accept_anyone(self, c, e):
    """Takes the first link still waiting for whoever says hello."""
    c.ch.send(pb.Envelope(id=e.id, hello_reply=pb.HelloReply(
        protocol_version=PROTOCOL_VERSION, participant=self.me, name="broken")))
    self.waiting()[0].chan = c.ch
    self.incoming.remove(c)


handshake.Acceptor.advance = accept_anyone
example = runpy.run_path(os.path.join(src, "examples", "python_soil", "soil_participant.py"))
example["rc"].serve(example["LumpedSoil"]())
