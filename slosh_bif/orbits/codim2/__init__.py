"""Two-parameter continuation of bifurcations of periodic orbits of (9) and of (8): fold (LP),
period doubling (PD), pitchfork (BP) and Neimark-Sacker (NS) curves, one problem class each on a
shared minimally augmented base over either model's orbit equations (multiple shooting of (9),
the stroboscopic map of (8)), their codimension-2 points, and the curve result object."""

from slosh_bif.lazy import lazy_names

# public name -> the module that defines it, loaded on first use: a caller that needs one curve
# kind (a one-parameter family's pitchfork test, say) does not import the impact model's curves
_WHERE = {
    "BifurcationCurve": "curves",
    "CurveSeed": "curves",
    "trace_curve": "curves",
    "curve_problem": "curves",
    "CURVE_PROBLEMS": "curves",
    "CURVE_OPTIONS": "curves",
    "CODIM2_KINDS": "curves",
    "curve_boundary": "curves",
    "MinAugCurveProblem": "minaug",
    "FoldCurveProblem": "multiplier_curves",
    "FlipCurveProblem": "multiplier_curves",
    "PitchforkCurveProblem": "multiplier_curves",
    "repeats_early": "multiplier_curves",
    "MEETS_PARENT": "multiplier_curves",
    "TorusCurveProblem": "torus",
    "corrected_at": "crossing",
}

__all__ = list(_WHERE)


__getattr__, __dir__ = lazy_names(__name__, _WHERE)
