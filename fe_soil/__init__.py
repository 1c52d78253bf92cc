"""A 3D finite-element soil (FEniCSx) for ground-borne vibration: a layered
block under and beside the track, absorbing boundaries, sleeper footprints
and surface receivers. The measures of fe_soil.measures need numpy only."""
from .params import Footprint, Layer, SoilParams, mesh_size, rayleigh_speed

__all__ = ["FESoil", "Footprint", "Layer", "SoilParams", "mesh_size", "rayleigh_speed"]


def FESoil(*args, **kwargs):  # noqa: N802  (imports dolfinx only when used)
    from .model import FESoil as _FESoil

    return _FESoil(*args, **kwargs)
