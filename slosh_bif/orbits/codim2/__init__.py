"""Two-parameter continuation of bifurcations of periodic orbits of (9) and of (8): fold (LP),
period doubling (PD), pitchfork (BP) and Neimark-Sacker (NS) curves, one problem class each on a
shared minimally augmented base over either model's orbit equations (multiple shooting of (9),
the stroboscopic map of (8)), their codimension-2 points, and the curve result object."""

from slosh_bif.orbits.codim2.curves import (
    CODIM2_KINDS,
    CURVE_OPTIONS,
    CURVE_PROBLEMS,
    BifurcationCurve,
    CurveSeed,
    curve_problem,
    trace_curve,
)
from slosh_bif.orbits.codim2.impact_curves import ImpactCurveSeed, trace_impact_curve
from slosh_bif.orbits.codim2.impact_strobe import ImpactStrobe
from slosh_bif.orbits.codim2.minaug import MinAugCurveProblem
from slosh_bif.orbits.codim2.multiplier_curves import (
    MEETS_PARENT,
    FlipCurveProblem,
    FoldCurveProblem,
    PitchforkCurveProblem,
    repeats_early,
)
from slosh_bif.orbits.codim2.torus import TorusCurveProblem

__all__ = [
    "BifurcationCurve",
    "CurveSeed",
    "trace_curve",
    "curve_problem",
    "CURVE_PROBLEMS",
    "MinAugCurveProblem",
    "FoldCurveProblem",
    "FlipCurveProblem",
    "PitchforkCurveProblem",
    "TorusCurveProblem",
    "CURVE_OPTIONS",
    "CODIM2_KINDS",
    "ImpactCurveSeed",
    "trace_impact_curve",
    "ImpactStrobe",
    "repeats_early",
    "MEETS_PARENT",
]
