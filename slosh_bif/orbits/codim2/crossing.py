"""A curve of orbit bifurcations of (9) (or of (8)) read at a value of its first parameter: the
point between two computed points corrected on the curve's own minimally augmented system at that
value (Newton in the orbit's states and p2, p1 held), not interpolated linearly between them. The chart's
critical forcing Abar_c(sigma) (:mod:`slosh_bif.studies.chart.critical`) then carries the
corrector's error instead of the points' spacing: where a fold curve turns between two points the
interpolation is off by up to 1e-3 (the Fig. 10 set at sigma = -1.5: 0.32079 against 0.32068).
"""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.orbits.codim2.curves import curve_problem

__all__ = ["corrected_at", "CROSSING_TOL"]

CROSSING_TOL = 1e-9  # Newton's update at the corrected point (the curves' own corrector tolerance)


def corrected_at(curve, params: Params, value: float, segment: int, orbits=None) -> float | None:
    """p2 of ``curve`` at p1 = ``value``, corrected from the linear interpolation over its points
    ``segment`` and ``segment + 1`` (which bracket ``value``), on the curve problem of its kind
    built at ``params`` with the curve's arcs and period (``orbits``: the orbit equations of
    another model, :func:`~slosh_bif.orbits.impact.curves.impact_corrected_at`); None where the
    curve is not one of (9) and no ``orbits`` are given, Newton does not converge, or it
    converges off the segment (beyond half the segment's own span in p2)."""
    branch = curve.branch
    if "(9)" not in branch.kind and orbits is None:
        return None
    s, x = branch.p, branch.x
    i = int(segment)
    t = (value - s[i]) / (s[i + 1] - s[i])
    x0 = x[i] + t * (x[i + 1] - x[i])
    extra = 2 if curve.kind == "NS" else 1  # p2 (and kappa) follow the orbit's states
    try:
        at = params.replace(**{curve.p1: float(value), curve.p2: float(x0[-extra])})
        problem = curve_problem(
            at,
            curve.kind,
            curve.p1,
            curve.p2,
            segments=(len(branch.names) - extra) // 4,
            period_multiple=curve.period_multiple,
            orbits=orbits,
        )
        problem.init_borders(x0, float(value))
        run = newton_solve(problem, x0, float(value), tol=CROSSING_TOL, max_iter=8)
    except (ValueError, ConvergenceError, np.linalg.LinAlgError):
        return None
    if not run.converged:
        return None
    p2 = float(run.x[-extra])
    lo, hi = sorted((float(x[i, -extra]), float(x[i + 1, -extra])))
    margin = 0.5 * (hi - lo) + 1e-6 * (1 + abs(p2))
    return p2 if lo - margin <= p2 <= hi + margin else None
