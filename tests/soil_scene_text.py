"""Shared by the soil comparison tests (tests/fe_soil/test_cosim.py,
tests/green_soil/test_fe_coupled.py): the text of scenes/soil.toml with a
wheel at 18 km/h on 30 sleepers for 0.2 s at H = 5e-4 s, writing its
ballast forces."""
import os

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))

EDITS = (("speed_kmh = 300.0", "speed_kmh = 18.0"),
         ("initial_position = 2.0", "initial_position = 8.0"),
         ("count = 50 ", "count = 30 "), ("end_time = 0.25", "end_time = 0.2"),
         ("macro_step = 1e-4", "macro_step = 5e-4"),
         ("[simulation]", "[output]\nballast_forces = true\n\n[simulation]"))


def wheel_at_18_kmh():
    """The edited text; AssertionError names an edit whose text the scene no
    longer holds."""
    with open(os.path.join(SRC, "scenes", "soil.toml")) as f:
        text = f.read()
    for old, new in EDITS:
        if old not in text:
            raise AssertionError("scenes/soil.toml no longer holds %r" % old)
        text = text.replace(old, new)
    return text
