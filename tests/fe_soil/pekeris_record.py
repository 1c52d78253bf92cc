"""Shared by the whole-record tests (test_whole_record.py at f_max 10 Hz,
test_whole_record_full.py at the scene's 20 Hz): the homogeneous half-space
(c_S = 100 m/s, rho = 2000, nu = 1/4, no damping) under a 10 kN Ricker on
the middle one of 21 sleepers' 0.25 x 2.5 m footprints, the block the
[soil] keys make of it, and each receiver's vertical velocity from the
load's start to 0.6 s against the closed form of Pekeris averaged over the
footprint (fe_soil/record_check.py)."""
from types import SimpleNamespace

import numpy as np

from support import HALF_SPACE

from fe_soil import config, lamb, record_check
from fe_soil.model import FESoil

F, T_END, MIDDLE = 1e4, 0.6, 10
# Issue 38's bounds: the whole record, then the direct waves.
BOUNDS = {"nrms": 0.25, "ppv": 0.05, "kb": 0.10, "band_db": 1.0,
          "arrival": 0.02, "peak": 0.10, "direct_nrms": 0.15}


def block(**keys):
    """The block of a [soil] table on the half-space: f_max 10 Hz, growth
    1.1, receivers 4 to 32 m, resolve_to 16, no static far field, the other
    keys at their defaults; `keys` replace or add keys."""
    table = {"model": "fe", "f_max": 10.0, "growth": 1.1, "receivers": [4.0, 8.0, 16.0, 32.0],
             "resolve_to": 16.0, "static_reach": 0.0,
             "layers": [{"density": HALF_SPACE.density, "shear_wave_speed": HALF_SPACE.shear_speed,
                         "poisson": HALF_SPACE.poisson}]}
    table.update(keys)
    sleepers = [SimpleNamespace(x=0.6 * i, length=0.25, width=2.5, y=0.0) for i in range(21)]
    return config.block_params(config.parse(table), sleepers)[0]


def whole_record(p, judged, fc):
    """({distance: measures} at the receivers `judged` m across, the soil)
    under a Ricker of centre fc Hz peaking at 1.2 / fc."""
    t0 = 1.2 / fc
    soil = FESoil(p)
    f = lamb.ricker(fc, t0)[0]
    H = soil.dt
    before, after = np.zeros(21), np.zeros(21)
    for k in range(int(np.ceil(T_END / H))):
        before[MIDDLE], after[MIDDLE] = F * f(k * H), F * f((k + 1) * H)
        soil.advance(k * H, H, before, after)
    t, v = soil.receiver_series()
    fp = p.footprints[MIDDLE]
    out = {}
    for i, (x, y) in enumerate(p.receivers):
        if y not in judged:
            continue
        ref = record_check.footprint_reference(t, (x, y), (fp.x, fp.y, fp.along, fp.across),
                                               HALF_SPACE.shear_modulus, HALF_SPACE.shear_speed,
                                               F, fc, t0)
        end = record_check.direct_end(t0 - 1.0 / fc, y, (p.length, p.half_width, p.depth),
                                      HALF_SPACE.shear_speed)
        out[y] = record_check.compare(t, -v[:, i, 2], ref, t0, end, p.f_max)
    return out, soil
