"""The model: parameters and presets, the restitution law, the slow invariant manifold, and the
equations of the vibro-impact model (8) and the smooth model (9).

Everything else in the package is built on this folder; it imports nothing from the rest.
``_generated/`` is written by ``derivations/`` (never by hand).
"""

from slosh_bif.model.equations import ImpactModel, SmoothModel
from slosh_bif.model.manifold import ManifoldProjection, project_on_manifold
from slosh_bif.model.params import FIELDS, Params
from slosh_bif.model.presets import (
    PRESETS,
    Preset,
    get_preset,
    state_from_uv,
    uv_from_state,
)
from slosh_bif.model.restitution.on_manifold import ManifoldLaw

__all__ = [
    "Params",
    "FIELDS",
    "Preset",
    "PRESETS",
    "get_preset",
    "state_from_uv",
    "uv_from_state",
    "SmoothModel",
    "ImpactModel",
    "ManifoldLaw",
    "ManifoldProjection",
    "project_on_manifold",
]
