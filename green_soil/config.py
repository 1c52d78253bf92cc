"""The Green's-function soil's configuration: the scene's [soil] table with
model = "green", checked key by key (numpy and the standard library only).

    [soil]
    model = "green"
    f_max = 150.0                # Hz, the highest frequency of the Green's functions
    memory = 1.0                 # s, the responses' length (at most the run's)
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

import math

from fe_soil.params import Layer

TOP_KEYS = {"model", "f_max", "memory", "receivers", "receiver_x", "layers", "workers"}
LAYER_KEYS = {"thickness", "density", "shear_wave_speed", "poisson", "damping"}
DEFAULTS = {"f_max": 150.0, "memory": 1.0, "receivers": [8.0, 16.0, 32.0]}


class ConfigError(ValueError):
    """A key of the [soil] table that cannot be used; the message names it."""


def _number(table, key, where, lo=None, hi=None, lo_open=True, default=None):
    value = table.get(key, default)
    name = "[soil] %s%s" % (where, key)
    if value is None:
        raise ConfigError("%s is missing" % name)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError("%s must be a finite number (got %r)" % (name, value))
    value = float(value)
    if lo is not None and (value <= lo if lo_open else value < lo):
        raise ConfigError("%s must be %s %g (got %g)" % (name, ">" if lo_open else ">=", lo, value))
    if hi is not None and value >= hi:
        raise ConfigError("%s must be < %g (got %g)" % (name, hi, value))
    return value


def _layer(layer, k, last):
    where = "layers[%d]." % (k + 1)
    unknown = sorted(set(layer) - LAYER_KEYS)
    if unknown:
        raise ConfigError("[soil] %s%s is not a key of a layer (its keys: %s)"
                          % (where, unknown[0], ", ".join(sorted(LAYER_KEYS))))
    thickness = (1.0 if last and "thickness" not in layer
                 else _number(layer, "thickness", where, lo=0.0))
    return Layer(thickness=thickness,
                 density=_number(layer, "density", where, lo=0.0),
                 shear_speed=_number(layer, "shear_wave_speed", where, lo=0.0),
                 poisson=_number(layer, "poisson", where, lo=0.0, hi=0.5, lo_open=False),
                 damping=_number(layer, "damping", where, lo=0.0, hi=0.5, lo_open=False,
                                 default=0.0))


def parse(table):
    """The checked settings of a [soil] table, as a dict of plain values."""
    unknown = sorted(set(table) - TOP_KEYS)
    if unknown:
        raise ConfigError("[soil] %s is not a key of the Green's-function soil (its keys: %s)"
                          % (unknown[0], ", ".join(sorted(TOP_KEYS))))
    if table.get("model", "green") != "green":
        raise ConfigError("[soil] model is %r; this program is the Green's-function soil "
                          "(model = \"green\")" % table.get("model"))
    out = {"f_max": _number(table, "f_max", "", lo=1.0, hi=1000.0, default=DEFAULTS["f_max"]),
           "memory": _number(table, "memory", "", lo=0.0, hi=60.0, default=DEFAULTS["memory"])}
    receivers = table.get("receivers", DEFAULTS["receivers"])
    if not isinstance(receivers, list) or len(receivers) > 64:
        raise ConfigError("[soil] receivers must be a list of at most 64 distances (got %r)"
                          % (receivers,))
    out["receivers"] = [_number({"receivers": r}, "receivers", "", lo=0.0, lo_open=False)
                        for r in receivers]
    out["receiver_x"] = _number(table, "receiver_x", "") if "receiver_x" in table else None
    workers = table.get("workers", 0)
    if isinstance(workers, bool) or not isinstance(workers, int) or not 0 <= workers <= 256:
        raise ConfigError("[soil] workers must be an integer from 0 (the usable cores) to 256 "
                          "(got %r)" % (workers,))
    out["workers"] = workers
    layers = table.get("layers")
    if not isinstance(layers, list) or not layers or not all(isinstance(l, dict) for l in layers):
        raise ConfigError("[soil] layers is missing: give one [[soil.layers]] table or more, top "
                          "down, each with thickness, density, shear_wave_speed, poisson, damping")
    if len(layers) > 64:
        raise ConfigError("[soil] layers: at most 64 layers (got %d)" % len(layers))
    out["layers"] = [_layer(l, k, k == len(layers) - 1) for k, l in enumerate(layers)]
    return out
