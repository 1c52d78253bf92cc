"""The keys the soils' [soil] tables share, checked one way for all of
them: numbers with their bounds, the receivers' distances, the layer
table (thickness, density, shear_wave_speed, poisson, damping). The FE soil
(fe_soil/config.py) and the Green's-function soil (green_soil/config.py)
read their tables with these; each keeps its own keys and limits. numpy-free,
the standard library only, so that the checks run anywhere."""
from __future__ import annotations

import math

from .params import Layer

LAYER_KEYS = {"thickness", "density", "shear_wave_speed", "poisson", "damping"}
MAX_RECEIVERS = 64  # each a point search or a set of responses, and a channel per step


class ConfigError(ValueError):
    """A key of the [soil] table that cannot be used; the message names it."""


def number(table, key, where, lo=None, hi=None, lo_open=True, default=None):
    """table[key] (or default) as a float within (lo, hi) (lo_open: lo
    itself refused); where: the prefix of the key in messages ("" or
    "layers[2].")."""
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


def optional_number(table, key):
    """table[key] as a float, or None when the table does not give it."""
    return number(table, key, "") if key in table else None


def numbers(table, key, default, count=None):
    """A list of one or more numbers >= 0 (exactly count of them if given)."""
    value = table.get(key, default)
    if not isinstance(value, list) or not value or (count is not None and len(value) != count):
        raise ConfigError("[soil] %s must be a list of %s numbers (got %r)"
                          % (key, count if count else "one or more", value))
    return [number({key: v}, key, "", lo=0.0, lo_open=False) for v in value]


def receivers(table, default, at_least_one=True):
    """The receivers' distances from the track axis (m, >= 0): at most
    MAX_RECEIVERS of them; at_least_one: an empty list is refused."""
    value = table.get("receivers", default)
    if isinstance(value, list) and len(value) > MAX_RECEIVERS:
        raise ConfigError("[soil] receivers lists %d distances; at most %d (each costs a point "
                          "search or a set of responses when the soil is built and a history "
                          "channel at every step)" % (len(value), MAX_RECEIVERS))
    if not isinstance(value, list) or (at_least_one and not value):
        raise ConfigError("[soil] receivers must be a list of %s numbers (got %r)"
                          % ("one or more" if at_least_one else "at most %d" % MAX_RECEIVERS,
                             value))
    return [number({"receivers": v}, "receivers", "", lo=0.0, lo_open=False) for v in value]


def layer(table, k, last, damping_hi):
    """Layer k (0-based) of [[soil.layers]]; the last one's thickness may be
    left out (it is the half-space, or reaches the block's bottom)."""
    where = "layers[%d]." % (k + 1)
    unknown = sorted(set(table) - LAYER_KEYS)
    if unknown:
        raise ConfigError("[soil] %s%s is not a key of a layer (its keys: %s)"
                          % (where, unknown[0], ", ".join(sorted(LAYER_KEYS))))
    thickness = (1.0 if last and "thickness" not in table
                 else number(table, "thickness", where, lo=0.0))
    return Layer(thickness=thickness,
                 density=number(table, "density", where, lo=0.0),
                 shear_speed=number(table, "shear_wave_speed", where, lo=0.0),
                 poisson=number(table, "poisson", where, lo=0.0, hi=0.5, lo_open=False),
                 damping=number(table, "damping", where, lo=0.0, hi=damping_hi, lo_open=False,
                                default=0.0))


def layers(table, damping_hi, max_layers=None):
    """The [[soil.layers]] tables, top down, as Layer values; damping below
    damping_hi; at most max_layers of them if given."""
    value = table.get("layers")
    if not isinstance(value, list) or not value or not all(isinstance(l, dict) for l in value):
        raise ConfigError("[soil] layers is missing: give one [[soil.layers]] table or more, top "
                          "down, each with thickness, density, shear_wave_speed, poisson, damping")
    if max_layers is not None and len(value) > max_layers:
        raise ConfigError("[soil] layers: at most %d layers (got %d)" % (max_layers, len(value)))
    return [layer(l, k, k == len(value) - 1, damping_hi) for k, l in enumerate(value)]
