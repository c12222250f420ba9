"""Special points between two accepted points: detection by sign changes, location by Brent.

Test functions along the branch: the parameter component of the tangent, ``t_p``, changes sign
at a fold (LP); the determinant of the bordered matrix changes sign at a simple branch point
(BP), and not at a fold; a problem's own ``test_functions`` add further kinds (PD, NS). Each is
located by Brent's method on the arclength from the last point before the sign change, each
evaluation a full corrector solve.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation.branch import BRANCH_POINT, FOLD
from slosh_bif.continuation.corrector import Point, correct, make_point
from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.continuation.problem import capabilities
from slosh_bif.roots import brent

__all__ = ["locate", "special_between", "TEST_MEANING"]


def locate(problem, a: Point, b: Point, h, which, opts, predict=None):
    """Brent on the arclength s in (0, h) between point a and the step's point b for a zero of
    test function ``which``, each trial point predicted as the step was (``predict(s)``, the
    engine's guess at arclength s; along the tangent when not given), so that s = h gives b.

    Returns (point, note). Exactly at a branch point the corrector's matrix is singular, and
    Brent may step so close that the correction fails: then the best point found so far is
    returned, with a note of how far from the zero it may be.
    """
    seen = {0.0: a, h: b}  # the ends, whose tests are known: Brent starts from them
    predict = predict or (lambda s: a.u + s * a.t)

    def point(s):
        guess = predict(s)
        # start from the nearest trial's point (or end), moved along: the same hyperplane t.(u - guess) = 0
        near = min(seen, key=lambda r: abs(r - s))
        guess = guess + (seen[near].u - predict(near))
        u, _ = correct(problem, guess, a.t, opts, strict=True)
        if u is None:
            raise ConvergenceError("corrector failed while locating a special point")
        seen[s] = make_point(problem, u, a.t)
        return seen[s]

    try:
        test = a.tests[which], b.tests[which]
        s = brent(lambda s: point(s).tests[which], 0.0, h, xtol=opts.locate_tol, fa=test[0], fb=test[1])
        return dataclasses.replace(seen[s]), ""  # a copy: an end is the branch's own point
    except ConvergenceError:
        if len(seen) == 2:  # no trial converged
            raise
        left = [s for s in seen if np.sign(seen[s].tests[which]) == np.sign(a.tests[which])]
        right = [s for s in seen if s not in left]
        gap = min(right) - max(left)
        best = min((s for s in seen if 0.0 < s < h), key=lambda s: abs(seen[s].tests[which]))
        return seen[best], f" (located to within arclength {gap:.2g}: the corrector fails closer in)"


TEST_MEANING = {
    FOLD: "fold: the tangent's parameter component changes sign",
    BRANCH_POINT: "branch point: the bordered Jacobian's determinant changes sign",
}


def special_between(problem, a: Point, b: Point, h, opts, predict=None):
    found = []
    tests = [(0, FOLD, opts.detect_folds), (1, BRANCH_POINT, opts.detect_branch_points)]
    caps = capabilities(problem)
    tests += [(2 + i, kind, True) for i, kind in enumerate(caps.test_kinds)]
    confirm = caps.confirm
    for which, kind, enabled in tests:
        floor = caps.test_floor.get(kind, 0.0)
        if (
            enabled
            and np.sign(a.tests[which]) * np.sign(b.tests[which]) < 0
            and max(abs(a.tests[which]), abs(b.tests[which])) >= floor
        ):
            try:
                q, note = locate(problem, a, b, h, which, opts, predict)
            except (ConvergenceError, ValueError) as err:
                if confirm is not None and which >= 2 and confirm(kind, b.u[:-1], b.u[-1]) is None:
                    continue  # what the problem says is none at the step's end (a sign flip of rounding)
                q = dataclasses.replace(b, iterations=0, located=False)
                q.message = f"{kind} detected, not located: {err}"
            else:
                q.message = TEST_MEANING.get(kind, f"{kind}: test function changes sign")
                if confirm is not None and which >= 2:
                    q.message = confirm(kind, q.u[:-1], q.u[-1])
                    if q.message is None:
                        continue
                q.message += note
            q.kind, q.bracket = kind, (a.u[-1], b.u[-1])
            found.append(q)
    found.sort(key=lambda q: (q.u - a.u) @ a.t)
    return found
