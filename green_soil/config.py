"""The Green's-function soil's configuration: the scene's [soil] table with
model = "green", checked key by key (numpy and the standard library only).

    [soil]
    model = "green"
    f_max = 150.0                # Hz, the highest frequency of the Green's functions
    memory = 1.0                 # s, the footprints' responses' length (at most the run's)
    receiver_memory = 1.0        # optional, s: the receivers' (default: memory)
    receivers = [8.0, 16.0]      # m from the track axis
    receiver_x = 15.0            # optional, m along the rail (default: the middle)
    workers = 0                  # processes computing the Green's functions (0: the usable cores)
    [[soil.layers]]              # top down; the last is the half-space
    thickness = 1.4              # m
    density = 1800.0             # kg/m^3
    shear_wave_speed = 128.0     # m/s
    poisson = 0.375
    damping = 0.044              # material damping ratio (hysteretic)
"""
from __future__ import annotations

from fe_soil import soil_table
from fe_soil.soil_table import ConfigError

TOP_KEYS = {"model", "f_max", "memory", "receiver_memory", "receivers", "receiver_x", "layers",
            "workers"}
DEFAULTS = {"f_max": 150.0, "memory": 1.0, "receivers": [8.0, 16.0, 32.0]}
MAX_LAYERS = 64

def parse(table):
    """The checked settings of a [soil] table, as a dict of plain values."""
    unknown = sorted(set(table) - TOP_KEYS)
    if unknown:
        raise ConfigError("[soil] %s is not a key of the Green's-function soil (its keys: %s)"
                          % (unknown[0], ", ".join(sorted(TOP_KEYS))))
    if table.get("model", "green") != "green":
        raise ConfigError("[soil] model is %r; this program is the Green's-function soil "
                          "(model = \"green\")" % table.get("model"))
    out = {"f_max": soil_table.number(table, "f_max", "", lo=1.0, hi=1000.0, default=DEFAULTS["f_max"]),
           "memory": soil_table.number(table, "memory", "", lo=0.0, hi=60.0, default=DEFAULTS["memory"])}
    out["receiver_memory"] = (soil_table.number(table, "receiver_memory", "", lo=0.0, hi=60.0)
                              if "receiver_memory" in table else out["memory"])
    out["receivers"] = soil_table.receivers(table, DEFAULTS["receivers"], at_least_one=False)
    out["receiver_x"] = soil_table.optional_number(table, "receiver_x")
    workers = table.get("workers", 0)
    if isinstance(workers, bool) or not isinstance(workers, int) or not 0 <= workers <= 256:
        raise ConfigError("[soil] workers must be an integer from 0 (the usable cores) to 256 "
                          "(got %r)" % (workers,))
    out["workers"] = workers
    out["layers"] = soil_table.layers(table, damping_hi=0.5, max_layers=MAX_LAYERS)
    return out
