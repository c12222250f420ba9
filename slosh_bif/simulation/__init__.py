"""Direct simulation of the smooth model (9) and the vibro-impact model (8) (integrated by
:mod:`slosh_bif.flows`), the regime classifier and regime maps, wavelets, and their output."""

from slosh_bif.flows.integrator import HAVE_NUMBA, integrate, integrate_grid
from slosh_bif.flows.noise import BandLimitedNoise, band_limited_noise
from slosh_bif.simulation.direct import Simulation, simulate
from slosh_bif.simulation.regimes import (
    REGIMES,
    RegimeMap,
    RegimeSummary,
    classify,
    regime_map,
)
from slosh_bif.simulation.vibro_impact import ImpactTrajectory, simulate_impact

__all__ = [
    "simulate",
    "Simulation",
    "simulate_impact",
    "ImpactTrajectory",
    "integrate",
    "integrate_grid",
    "HAVE_NUMBA",
    "band_limited_noise",
    "BandLimitedNoise",
    "classify",
    "RegimeSummary",
    "regime_map",
    "RegimeMap",
    "REGIMES",
]
