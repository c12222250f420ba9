"""Two-parameter continuation of bifurcations of periodic orbits of (9): fold (LP), period
doubling (PD) and Neimark-Sacker (NS) curves by minimally augmented systems, their
codimension-2 points, and the curve result object."""

from slosh_bif.orbits.codim2.curves import CODIM2_KINDS, CURVE_OPTIONS, BifurcationCurve, trace_curve
from slosh_bif.orbits.codim2.minaug import CURVE_KINDS, MultiplierCurveProblem
from slosh_bif.orbits.codim2.torus import TorusCurveProblem

__all__ = ["BifurcationCurve", "trace_curve", "MultiplierCurveProblem", "TorusCurveProblem", "CURVE_KINDS", "CURVE_OPTIONS", "CODIM2_KINDS"]
