"""Periodic orbits of the smooth model (9): shooting with Floquet multipliers, families with
branch switching, start orbits (from a simulation or from the slow flow), the scan for every
family, and their output.

Seams to the other wings (documented in ``docs/architecture.md`` and allowed by the import
contract): :mod:`.shooting` integrates with :mod:`slosh_bif.flows.integrator`, and
:mod:`.starts` takes start guesses from :mod:`slosh_bif.simulation` and :mod:`slosh_bif.slowflow`.
"""

import importlib

# public name -> the module that defines it, loaded on first use: a caller of one wing (the impact
# model's orbits, say) does not pay for the import of the others
_WHERE = {
    "SHOOTING_OPTIONS": "families",
    "trace_orbits": "families",
    "OrbitBranch": "orbit_branch",
    "OrbitFamily": "orbit_branch",
    "mirror": "orbit_branch",
    "orbit_at": "orbit_tools",
    "periodic_orbit": "orbit_tools",
    "on_traced_branch": "scan",
    "scan_families": "scan",
    "NO_SWITCHING": "settings",
    "BranchingSettings": "settings",
    "ShootingSettings": "settings",
    "StartSettings": "settings",
    "PeriodicOrbit": "shooting",
    "ShootingProblem": "shooting",
    "StabilityLoss": "stability",
    "loss_of_stability": "stability",
    "StartOrbit": "starts",
    "orbit_from_simulation": "starts",
    "orbit_from_slow_flow": "starts",
    "settle_and_shoot": "starts",
    "slow_flow_start": "starts",
}

__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        value = getattr(importlib.import_module(f"slosh_bif.orbits.{_WHERE[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'slosh_bif.orbits' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
