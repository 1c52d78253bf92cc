"""Shared by the Green's-function soil tests: the import path, the
homogeneous half-space of Pekeris' problem and a layered ground."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))

try:
    import scipy  # noqa: F401
except ImportError as e:  # pragma: no cover
    print(f"SKIP: scipy is not importable ({e}); scripts/install-deps.sh --green installs python3-scipy")
    sys.exit(77)

from fe_soil import lamb  # noqa: E402
from fe_soil.params import Layer  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from report_table import report_rows  # noqa: E402,F401  (the green tests' support.report_rows)

# nu = 1/4, elastic: Pekeris' closed form (fe_soil/lamb.py) applies.
HALF_SPACE = [Layer(thickness=1.0, density=1800.0, shear_speed=200.0, poisson=0.25, damping=0.0)]

# The ground-vibration scene's layers (scenes/ground_vibration.toml).
LAYERED = [Layer(1.4, 1800.0, 128.0, 0.375, 0.044), Layer(2.7, 1800.0, 176.0, 0.195, 0.038),
           Layer(1.0, 1800.0, 355.0, 0.478, 0.037)]


def elastic(layers):
    return [Layer(l.thickness, l.density, l.shear_speed, l.poisson, 0.0) for l in layers]


def pekeris_footprint(t, dx, dy, a, b, layer, f, df, nodes=300, n_gauss=6):
    """Pekeris' point response convolved with (f, df) and averaged over an
    a x b footprint whose centre is (dx, dy) from the receiver (Gauss)."""
    xg, wg = np.polynomial.legendre.leggauss(n_gauss)
    out = np.zeros_like(t)
    for xa, wa in zip(0.5 * a * xg, 0.5 * wg):
        for yb, wb in zip(0.5 * b * xg, 0.5 * wg):
            r = math.hypot(dx + xa, dy + yb)
            out += wa * wb * lamb.convolve(t, r, layer.shear_modulus, layer.shear_speed, f, df,
                                           nodes=nodes)
    return out
