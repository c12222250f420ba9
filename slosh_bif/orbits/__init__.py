"""Periodic orbits of the smooth model (9): shooting with Floquet multipliers, families with
branch switching, start orbits (from a simulation or from the slow flow), the scan for every
family, and their output.

Seams to the other wings (documented in ``docs/architecture.md`` and allowed by the import
contract): :mod:`.shooting` integrates with :mod:`slosh_bif.flows.integrator`, and
:mod:`.starts` takes start guesses from :mod:`slosh_bif.simulation` and :mod:`slosh_bif.slowflow`.
"""

from slosh_bif.orbits.families import SHOOTING_OPTIONS, trace_orbits
from slosh_bif.orbits.orbit_branch import OrbitBranch, OrbitFamily, mirror
from slosh_bif.orbits.orbit_tools import orbit_at, periodic_orbit
from slosh_bif.orbits.scan import on_traced_branch, scan_families
from slosh_bif.orbits.settings import (
    NO_SWITCHING,
    BranchingSettings,
    ShootingSettings,
    StartSettings,
)
from slosh_bif.orbits.shooting import PeriodicOrbit, ShootingProblem
from slosh_bif.orbits.stability import StabilityLoss, loss_of_stability
from slosh_bif.orbits.starts import (
    StartOrbit,
    orbit_from_simulation,
    orbit_from_slow_flow,
    settle_and_shoot,
    slow_flow_start,
)

__all__ = [
    "ShootingProblem",
    "PeriodicOrbit",
    "periodic_orbit",
    "orbit_at",
    "trace_orbits",
    "ShootingSettings",
    "BranchingSettings",
    "StartSettings",
    "NO_SWITCHING",
    "OrbitFamily",
    "OrbitBranch",
    "mirror",
    "SHOOTING_OPTIONS",
    "StartOrbit",
    "orbit_from_simulation",
    "orbit_from_slow_flow",
    "slow_flow_start",
    "settle_and_shoot",
    "scan_families",
    "on_traced_branch",
    "loss_of_stability",
    "StabilityLoss",
]
