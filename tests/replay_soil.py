#!/usr/bin/env python3
"""A soil that computes nothing, for the conformance kit's own test. With
--record FILE it is the example soil on the Python SDK and writes every
reply it gives (the outputs of each statics and each macro step) to FILE,
one JSON line each; with --replay FILE it gives those replies again, in the
order they were recorded, whatever inputs it is sent. The kit's fixed
requests cannot tell the two apart; its inputs never sent before can.

  replay_soil.py SOURCE_DIR (--record|--replay) FILE [serve() options]"""
import json
import os
import runpy
import sys

import numpy as np

src = sys.argv.pop(1)
mode = sys.argv.pop(1)
path = sys.argv.pop(1)
if mode not in ("--record", "--replay"):
    sys.exit("replay_soil.py: the second argument is --record or --replay, not " + mode)
sys.path.insert(0, os.path.join(src, "sdk", "python"))
example = runpy.run_path(os.path.join(src, "examples", "python_soil", "soil_participant.py"))
Soil = example["LumpedSoil"]


class Recorder(Soil):
    def keep(self, call, out):
        with open(path, "a") as f:
            f.write(json.dumps({"call": call, "u": list(map(float, out[0]["displacement"])),
                                "v": list(map(float, out[0]["velocity"]))}) + "\n")
        return out

    def statics(self, inputs):
        return self.keep("statics", super().statics(inputs))

    def advance(self, t, H, inputs):
        return self.keep("advance", super().advance(t, H, inputs))


class Replayer(Soil):
    def __init__(self):
        super().__init__()
        self.queue = {"statics": [], "advance": []}
        with open(path) as f:
            for line in f:
                r = json.loads(line)
                self.queue[r["call"]].append(r)
        self.taken = {"statics": 0, "advance": 0}

    def replay(self, call):
        q = self.queue[call]
        r = q[min(self.taken[call], len(q) - 1)]
        self.taken[call] += 1
        self.u, self.v = np.array(r["u"]), np.array(r["v"])
        return self.outputs()

    def statics(self, inputs):
        self.origin = self.a = np.zeros(self.n)
        return self.replay("statics")

    def advance(self, t, H, inputs):
        return self.replay("advance")


example["rc"].serve(Recorder() if mode == "--record" else Replayer())
