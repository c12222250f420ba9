"""Periodic orbits of the full models. The modules here are the smooth model (9)'s (multiple
shooting, families with branch switching, start orbits from a simulation or the slow flow, the
scan for every family, their output) and the machinery both models share (Floquet multipliers
and what they say, settings, the curve problems of :mod:`.codim2`); the vibro-impact model (8)
has its own folder, :mod:`~slosh_bif.orbits.impact`.

Seams to the other wings (documented in ``docs/architecture.md`` and allowed by the import
contract): :mod:`~slosh_bif.orbits.shooting` integrates with
:mod:`slosh_bif.flows.smooth.integrator`, and :mod:`~slosh_bif.orbits.starts` takes start guesses
from :mod:`slosh_bif.simulation` and :mod:`slosh_bif.slowflow`.
"""

from slosh_bif.lazy import lazy_names

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


__getattr__, __dir__ = lazy_names(__name__, _WHERE)
