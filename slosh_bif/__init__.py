"""slosh_bif: continuation and bifurcation analysis of the equivalent mechanical model of
strongly nonlinear liquid sloshing (M. Farid and O. V. Gendelman).

The folders are the pipeline (``docs/architecture.md``)::

    model  <-  continuation  <-  {slowflow, orbits, simulation}  <-  studies  <-  cli

The names a user needs are re-exported here and loaded on first use, so ``import slosh_bif``
computes nothing and does not load the compiled integrator until it is asked for.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

# public name -> the subpackage that defines it
_EXPORTS = {
    "slosh_bif.model": (
        "Params",
        "FIELDS",
        "Preset",
        "PRESETS",
        "get_preset",
        "SmoothModel",
        "ImpactModel",
        "ManifoldLaw",
    ),
    "slosh_bif.continuation": ("Branch", "SpecialPoint", "ContinuationOptions", "ConvergenceError"),
    "slosh_bif.slowflow": (
        "SlowFlow",
        "AsymptoticsWarning",
        "frequency_response",
        "FrequencyResponse",
        "critical_forcing",
        "critical_curve",
        "CriticalCurve",
    ),
    "slosh_bif.orbits": (
        "ShootingProblem",
        "PeriodicOrbit",
        "periodic_orbit",
        "trace_orbits",
        "OrbitFamily",
        "settle_and_shoot",
        "orbit_from_simulation",
        "slow_flow_start",
        "orbit_from_slow_flow",
        "scan_families",
        "loss_of_stability",
        "ShootingSettings",
        "BranchingSettings",
        "StartSettings",
        "NO_SWITCHING",
    ),
    "slosh_bif.simulation": (
        "simulate",
        "Simulation",
        "simulate_impact",
        "ImpactTrajectory",
        "classify",
        "regime_map",
        "RegimeMap",
    ),
    "slosh_bif.studies": ("answer", "trust_map"),
}
_WHERE = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'slosh_bif' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
