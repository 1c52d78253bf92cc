"""Shared by the soil tests: scene files under scenes/ with edits of their
text, each edit checked to apply. wheel_at_18_kmh() (tests/fe_soil/
test_cosim.py, tests/green_soil/test_fe_coupled.py): scenes/soil.toml with a
wheel at 18 km/h on 30 sleepers for 0.2 s at H = 5e-4 s, writing its
ballast forces. train_cut(): scenes/ground_vibration_train.toml cut to a CI
run (tests/green_soil/test_train.py)."""
import os

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))

EDITS = (("speed_kmh = 300.0", "speed_kmh = 18.0"),
         ("initial_position = 2.0", "initial_position = 8.0"),
         ("count = 50 ", "count = 30 "), ("end_time = 0.25", "end_time = 0.2"),
         ("macro_step = 1e-4", "macro_step = 5e-4"),
         ("[simulation]", "[output]\nballast_forces = true\n\n[simulation]"))

# The train scene's whole train and track rule, for 0.1 s (1000 steps of
# the train and track, 100 of the soil) and two receivers.
TRAIN_CUT = (("end_time = 2.4 ", "end_time = 0.1 "),
             ("receivers = [8.0, 16.0, 32.0, 64.0]", "receivers = [8.0, 16.0]"))


def edited(scene, edits):
    """The text of scenes/<scene> with each (old, new) edit applied;
    AssertionError names an edit whose text the scene no longer holds."""
    with open(os.path.join(SRC, "scenes", scene)) as f:
        text = f.read()
    for old, new in edits:
        if old not in text:
            raise AssertionError("scenes/%s no longer holds %r" % (scene, old))
        text = text.replace(old, new)
    return text


def wheel_at_18_kmh():
    """The edited text of scenes/soil.toml."""
    return edited("soil.toml", EDITS)


def train_cut():
    """The edited text of scenes/ground_vibration_train.toml."""
    return edited("ground_vibration_train.toml", TRAIN_CUT)
