"""The keys the two soils' [soil] tables share (receivers, receiver_x,
[[soil.layers]]) go through one reader, fe_soil/soil_table.py: the same
mistake gets the same message from the FE soil's and the Green's-function
soil's check, and the limits each soil keeps for itself stay its own (an
empty receiver list and a damping ratio from 0.5 to 1 the FE soil only,
at most 64 layers the Green's-function soil only). No dolfinx needed."""
import os
import sys
import unittest

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, SRC)

from fe_soil import config as fe_config  # noqa: E402
from green_soil import config as green_config  # noqa: E402

LAYER = {"thickness": 2.0, "density": 1800.0, "shear_wave_speed": 150.0, "poisson": 0.3,
         "damping": 0.03}
HALF_SPACE = {"density": 1800.0, "shear_wave_speed": 300.0, "poisson": 0.3, "damping": 0.03}


def table(model, **changes):
    t = {"model": model, "receivers": [4.0, 8.0], "layers": [dict(LAYER), dict(HALF_SPACE)]}
    t.update(changes)
    return t


def message(parse, t):
    try:
        parse(t)
    except ValueError as e:
        return str(e)
    return None


class SharedKeys(unittest.TestCase):
    def both(self, **changes):
        return (message(fe_config.parse, table("fe", **changes)),
                message(green_config.parse, table("green", **changes)))

    def test_one_error_type(self):
        self.assertIs(fe_config.ConfigError, green_config.ConfigError)

    def test_the_same_mistake_gets_the_same_message(self):
        bad_layer = dict(LAYER, shear_wave_speed=-1.0)
        cases = [
            ({"receivers": [float(k) for k in range(65)]},
             "[soil] receivers lists 65 distances; at most 64"),
            ({"receivers": [4.0, -2.0]}, "[soil] receivers must be >= 0 (got -2)"),
            ({"receivers": [4.0, float("nan")]}, "[soil] receivers must be a finite number"),
            ({"receiver_x": "middle"}, "[soil] receiver_x must be a finite number"),
            ({"layers": [bad_layer, dict(HALF_SPACE)]},
             "[soil] layers[1].shear_wave_speed must be > 0 (got -1)"),
            ({"layers": [dict(LAYER, colour=1), dict(HALF_SPACE)]},
             "[soil] layers[1].colour is not a key of a layer"),
            ({"layers": [dict(LAYER), dict(HALF_SPACE, poisson=0.5)]},
             "[soil] layers[2].poisson must be < 0.5 (got 0.5)"),
            ({"layers": []}, "[soil] layers is missing"),
        ]
        for changes, start in cases:
            fe, green = self.both(**changes)
            self.assertIsNotNone(fe, changes)
            self.assertTrue(fe.startswith(start), (changes, fe))
            self.assertEqual(fe, green, changes)

    def test_not_a_list_of_receivers(self):
        fe, green = self.both(receivers=8.0)
        self.assertEqual(fe, "[soil] receivers must be a list of one or more numbers (got 8.0)")
        self.assertEqual(green, "[soil] receivers must be a list of at most 64 numbers (got 8.0)")

    def test_each_soil_keeps_its_own_limits(self):
        fe, green = self.both(receivers=[])
        self.assertIn("one or more", fe)
        self.assertIsNone(green)  # a run without receivers
        fe, green = self.both(layers=[dict(LAYER, damping=0.7), dict(HALF_SPACE)])
        self.assertIsNone(fe)
        self.assertEqual(green, "[soil] layers[1].damping must be < 0.5 (got 0.7)")
        fe, green = self.both(layers=[dict(LAYER)] * 64 + [dict(HALF_SPACE)], depth=200.0)
        self.assertEqual(green, "[soil] depth is not a key of the Green's-function soil (its "
                                "keys: f_max, layers, memory, model, receiver_memory, receiver_x, "
                                "receivers, workers)")
        self.assertIsNone(fe)
        green = message(green_config.parse, table("green", layers=[dict(LAYER)] * 64
                                                  + [dict(HALF_SPACE)]))
        self.assertEqual(green, "[soil] layers: at most 64 layers (got 65)")


if __name__ == "__main__":
    unittest.main()
