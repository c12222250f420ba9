"""The model: parameters and presets, the restitution law, the slow invariant manifold, and the
equations of the vibro-impact model (8) and the smooth model (9).

Everything else in the package is built on this folder; it imports nothing from the rest.
``_generated/`` is written by ``derivations/`` (never by hand).
"""

from slosh_bif.lazy import lazy_names

_WHERE = {
    "Params": "params",
    "FIELDS": "params",
    "Preset": "presets",
    "PRESETS": "presets",
    "get_preset": "presets",
    "state_from_uv": "presets",
    "uv_from_state": "presets",
    "SmoothModel": "equations",
    "ImpactModel": "equations",
    "ManifoldLaw": "restitution.on_manifold",
    "ManifoldProjection": "manifold",
    "project_on_manifold": "manifold",
}
__all__ = list(_WHERE)
__getattr__, __dir__ = lazy_names(__name__, _WHERE)
