"""Shared by the finite-element soil tests: skip (exit 77) when dolfinx is
missing; the homogeneous half-space and the pulse the wave tests use."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))

try:
    import dolfinx  # noqa: F401
except ImportError as e:  # pragma: no cover
    print(f"SKIP: dolfinx is not importable ({e}); scripts/install-deps.sh --fe installs python3-dolfinx")
    sys.exit(77)

from fe_soil.params import Footprint, Layer, SoilParams, graded_nodes, uniform_nodes  # noqa: E402,F401

HALF_SPACE = Layer(thickness=1.0, density=2000.0, shear_speed=100.0, poisson=0.25, damping=0.0)


def ricker(t, fc, t0):
    a = (math.pi * fc * (t - t0)) ** 2
    return (1.0 - 2.0 * a) * math.exp(-a)


def drive(soil, amplitude, fc, t0, t_end, H):
    """Advance under a vertical Ricker pulse on footprint 0; returns the
    times and the kinetic energy after each macro step."""
    n = int(round(t_end / H))
    times, energy = [], []
    for k in range(n):
        t = k * H
        soil.advance(t, H, [amplitude * ricker(t, fc, t0)], [amplitude * ricker(t + H, fc, t0)])
        times.append(t + H)
        energy.append(soil.kinetic_energy())
    return np.array(times), np.array(energy)
