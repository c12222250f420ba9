"""slosh_bif: continuation and bifurcation analysis of the equivalent mechanical model of
strongly nonlinear liquid sloshing (M. Farid and O. V. Gendelman).

The public names are re-exported here; nothing is computed at import.
"""

from .models import ImpactModel, SmoothModel
from .params import FIELDS, Params
from .presets import PRESETS, Preset, get_preset
from .vibro_impact import ImpactTrajectory, simulate_impact

__all__ = [
    "FIELDS",
    "ImpactModel",
    "ImpactTrajectory",
    "PRESETS",
    "Params",
    "Preset",
    "SmoothModel",
    "get_preset",
    "simulate_impact",
]
__version__ = "0.1.0"
