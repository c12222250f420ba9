"""Direct simulation of the smooth model (9) and the vibro-impact model (8) (integrated by
:mod:`slosh_bif.flows`), the regime classifier and regime maps, wavelets, and their output."""

from slosh_bif.lazy import lazy_names

# public name -> the module that defines it, loaded on first use: a shooting run that settles its
# start orbit by a simulation does not pay for the regime maps' process pools
_WHERE = {
    "simulate": "direct",
    "Simulation": "direct",
    "simulate_impact": "vibro_impact",
    "ImpactTrajectory": "vibro_impact",
    "classify": "regimes",
    "RegimeSummary": "regimes",
    "regime_map": "regimes",
    "RegimeMap": "regimes",
    "REGIMES": "regimes",
}

__all__ = sorted(_WHERE)


__getattr__, __dir__ = lazy_names(__name__, _WHERE)
