"""Special points between two accepted points: detection by sign changes, location by Brent.

Test functions along the branch: the parameter component of the tangent, ``t_p``, changes sign
at a fold (LP); the determinant of the bordered matrix changes sign at a simple branch point
(BP), and not at a fold; a problem's own ``test_functions`` add further kinds (PD, NS). Each is
located by Brent's method on the arclength from the last point before the sign change, each
evaluation a full corrector solve. A test with the same sign at both ends of a step is checked
again at the points located inside it: two zeros in one step around another special point are
found that way.
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


def locate(problem, a: Point, b: Point, h, which, opts, predict=None, within=None):
    """Brent on the arclength s in (0, h) between point a and the step's point b for a zero of
    test function ``which``, each trial point predicted as the step was (``predict(s)``, the
    engine's guess at arclength s; along the tangent when not given), so that s = h gives b.
    ``within = ((s0, p0), (s1, p1))``: search only between two points of the step already
    computed, p0 at arclength s0 and p1 at s1 (the step's ends by default).

    Returns (point, note, s). Exactly at a branch point the corrector's matrix is singular, and
    Brent may step so close that the correction fails: then the best point found so far is
    returned, with a note of how far from the zero it may be.
    """
    (s0, p0), (s1, p1) = within or ((0.0, a), (h, b))
    seen = {s0: p0, s1: p1}  # the ends, whose tests are known: Brent starts from them
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
        test = p0.tests[which], p1.tests[which]
        s = brent(lambda s: point(s).tests[which], s0, s1, xtol=opts.locate_tol, fa=test[0], fb=test[1])
        return dataclasses.replace(seen[s]), "", s  # a copy: an end is the branch's own point
    except ConvergenceError:
        if len(seen) == 2:  # no trial converged
            raise
        left = [s for s in seen if np.sign(seen[s].tests[which]) == np.sign(p0.tests[which])]
        right = [s for s in seen if s not in left]
        gap = min(right) - max(left)
        best = min((s for s in seen if s0 < s < s1), key=lambda s: abs(seen[s].tests[which]))
        return seen[best], f" (located to within arclength {gap:.2g}: the corrector fails closer in)", best


TEST_MEANING = {
    FOLD: "fold: the tangent's parameter component changes sign",
    BRANCH_POINT: "branch point: the bordered Jacobian's determinant changes sign",
}


def _changes(p0: Point, p1: Point, which, floor) -> bool:
    """Whether test ``which`` changes sign from p0 to p1, beyond the problem's floor for it at both
    ends: a value below the floor is zero to rounding and has no sign, so a test that rises from
    rounding at one end to a value at the other has not crossed zero (a pair of multipliers that
    nears the unit circle as the particle leaves the walls, and never reaches it)."""
    t0, t1 = p0.tests[which], p1.tests[which]
    return np.sign(t0) * np.sign(t1) < 0 and min(abs(t0), abs(t1)) >= floor


def special_between(problem, a: Point, b: Point, h, opts, predict=None):
    """The special points between a and the step's end b (at arclength h), in the order of the step.

    A test that changes sign over the step is located; one that does not may still cross zero
    twice inside it (a pair of Neimark-Sacker points around a fold, 1e-4 apart in sigma on the
    Fig. 10 period-2 branch): it is checked again at the points located in the step, and located
    in each part between them where it changes sign."""
    caps = capabilities(problem)
    tests = [(0, FOLD, opts.detect_folds), (1, BRANCH_POINT, opts.detect_branch_points)]
    tests += [(2 + i, kind, True) for i, kind in enumerate(caps.test_kinds)]
    tests = [(which, kind, caps.test_floor.get(kind, 0.0)) for which, kind, enabled in tests if enabled]
    found = []  # (arclength, point)
    quiet = []
    for which, kind, floor in tests:
        if _changes(a, b, which, floor):
            found += _special(problem, a, b, h, which, kind, opts, predict)
        else:
            quiet.append((which, kind, floor))
    inner = sorted(((s, q) for s, q in found if q.located and 0.0 < s < h), key=lambda item: item[0])
    for which, kind, floor in quiet if inner else ():
        parts = [(0.0, a), *inner, (h, b)]
        for lo, hi in zip(parts, parts[1:]):
            if _changes(lo[1], hi[1], which, floor):
                found += _special(problem, a, b, h, which, kind, opts, predict, (lo, hi))
    found.sort(key=lambda item: item[0])
    return [q for _, q in found]


def _special(problem, a, b, h, which, kind, opts, predict, within=None):
    """[(arclength, point)] of the special point of test ``which`` located between a and b (or
    ``within`` two points of the step): none when the problem's ``confirm`` drops it."""
    confirm = capabilities(problem).confirm
    try:
        q, note, s = locate(problem, a, b, h, which, opts, predict, within)
    except (ConvergenceError, ValueError) as err:
        end = within[1][1] if within else b
        if confirm is not None and which >= 2 and confirm(kind, end.u[:-1], end.u[-1]) is None:
            return []  # what the problem says is none at the step's end (a sign flip of rounding)
        q, s = dataclasses.replace(end, iterations=0, located=False), (within[1][0] if within else h)
        q.message = f"{kind} detected, not located: {err}"
    else:
        q.message = TEST_MEANING.get(kind, f"{kind}: test function changes sign")
        if confirm is not None and which >= 2:
            q.message = confirm(kind, q.u[:-1], q.u[-1])
            if q.message is None:
                return []
        q.message += note
    q.kind, q.bracket = kind, (a.u[-1], b.u[-1])
    return [(s, q)]
