"""A scene file read by a soil study's command line (fe_soil.study,
fe_soil.mitigation, green_soil.study): parsed as TOML, its [soil] model
checked; what is wrong ends the program with a message naming the file."""
from __future__ import annotations

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
