"""railcosim_sdk: write a railcosim co-simulation participant in Python,
physics only.

    import sys
    sys.path.insert(0, "<checkout>/sdk/python")
    import railcosim_sdk as rc

    class Soil(rc.Participant):
        name = "soil"                      # the participant the master asks for
        history = ("soil_peak_m",)         # a value per step (history.csv)
        results_fields = ("soil_m",)       # arrays at the end (soil.csv)

        def configure(self, config, interfaces): ...
        def statics(self, inputs): ...            # -> outputs
        def advance(self, t, H, inputs): ...      # -> outputs at t + H
        def save(self): ...                       # -> floats
        def restore(self, state): ...
        def history_values(self): ...             # -> floats
        def results(self): ...                    # -> arrays

    if __name__ == "__main__":
        rc.serve(Soil())                   # --listen, --config, --token-file

See participant.py for the contract of each method, server.py for serve()'s
command line, wire.py for where the protocol's schema is compiled, and
docs/participant-guide.md for a walk from nothing to a matching result.
Needs Debian's python3-protobuf, python3-numpy and protobuf-compiler.
"""

from .participant import (BadInterface, BadRequest, Footprint, Inputs, Interface, Participant,
                          Run, StepFailed, Waveform)
from .server import serve
from .waveforms import Sampled

__all__ = ["Participant", "Interface", "Footprint", "Inputs", "Waveform", "Sampled", "Run",
           "StepFailed", "BadInterface", "BadRequest", "serve"]
