"""Direct simulation: the compiled DOP853 integrator (scipy fallback), the smooth model (9) and the
event-driven vibro-impact model (8), band-limited noise (47), the regime classifier and regime
maps, wavelets, and their output."""

from slosh_bif.simulation.direct import Simulation, simulate
from slosh_bif.simulation.integrator import HAVE_NUMBA, integrate, integrate_grid
from slosh_bif.simulation.noise import BandLimitedNoise, band_limited_noise
from slosh_bif.simulation.regimes import REGIMES, RegimeMap, RegimeSummary, classify, regime_map
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
