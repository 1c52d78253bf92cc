"""A scene file read by a soil study's command line (fe_soil.study,
fe_soil.mitigation, green_soil.study): parsed as TOML, its [soil] model
checked; what is wrong ends the program with a message naming the file.
And a scene written back (toml_text), for the runs a study makes of it."""
from __future__ import annotations

import datetime
import math
import re
import sys
import tomllib


def read_scene(path: str, model: str, elsewhere: str = "") -> dict:
    """The scene at `path`, whose [soil] model must be `model`; `elsewhere`
    (e.g. "; a scene on the lumped soil is studied by `master study`") is
    appended to the message when it is another."""
    try:
        with open(path, "rb") as f:
            scene = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        sys.exit("%s: %s" % (path, e))
    got = scene.get("soil", {}).get("model")
    if got != model:
        sys.exit('%s: [soil] model must be "%s" (got %r)%s' % (path, model, got, elsewhere))
    return scene


class SceneWriteError(ValueError):
    """A value a scene file cannot hold, named by its dotted key."""


def _key(k):
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _string(k)


def _string(s):
    out = []
    for c in s:
        if c in '"\\':
            out.append("\\" + c)
        elif ord(c) < 0x20 or ord(c) == 0x7F:
            out.append("\\u%04x" % ord(c))
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def _value(v, where):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        return repr(v) if math.isfinite(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (datetime.date, datetime.time)):  # datetime is a date
        return v.isoformat()
    if isinstance(v, list):
        return "[" + ", ".join(_value(x, where) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join("%s = %s" % (_key(k), _value(x, where + "." + k))
                               for k, x in v.items()) + "}"
    raise SceneWriteError("%s: %r cannot be written into a scene file" % (where, v))


def toml_text(table, prefix=""):
    """The TOML text of a table as tomllib reads it: scalars, arrays, tables
    and arrays of tables (tomllib.loads(toml_text(t)) == t)."""
    lines, subs = [], []
    for k, v in table.items():
        name = prefix + _key(k)
        if isinstance(v, dict):
            subs.append(("[%s]" % name, v, name + "."))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            subs += [("[[%s]]" % name, x, name + ".") for x in v]
        else:
            lines.append("%s = %s" % (_key(k), _value(v, prefix + k)))
    for head, sub, pre in subs:
        lines += ["", head, toml_text(sub, pre)]
    return "\n".join(lines)
