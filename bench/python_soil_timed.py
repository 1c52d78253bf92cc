#!/usr/bin/env python3
"""The soil of examples/python_soil on the Python SDK, its physics timed for
bench/sdk_lockstep_bench: serves as the example does, and at every
GetResults writes "SECONDS CALLS" to --physics-file: the wall time spent
inside its advance() calls in that session, and their number.

  python_soil_timed.py --physics-file FILE [the example's options]
"""

import argparse
import os
import runpy
import time

here = os.path.dirname(os.path.abspath(__file__))
SOIL = runpy.run_path(os.path.join(here, "..", "examples", "python_soil", "soil_participant.py"))


class TimedSoil(SOIL["LumpedSoil"]):
    def __init__(self, path):
        self.path = path
        self.physics, self.calls = 0.0, 0

    def configure(self, config, interfaces):
        self.physics, self.calls = 0.0, 0
        return super().configure(config, interfaces)

    def advance(self, t, H, inputs):
        start = time.perf_counter()
        try:
            return super().advance(t, H, inputs)
        finally:
            self.physics += time.perf_counter() - start
            self.calls += 1

    def results(self):
        with open(self.path, "w") as f:
            f.write("%r %d\n" % (self.physics, self.calls))
        return super().results()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(add_help=False)
    parser.add_argument("--physics-file", required=True)
    mine, rest = parser.parse_known_args()
    SOIL["rc"].serve(TimedSoil(mine.physics_file), rest)
