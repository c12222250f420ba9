"""How the continuation engine (:mod:`.engine`) sizes its steps and stamps its points: the next
step after a correction (grow, shrink, keep the turn per step near ``max_angle``), whether a step
ran through the start (a closed loop), each point's stability computed once as it joins the
branch, and a step shortened where its two ends differ in stability with no special point
between them."""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.corrector import Point

__all__ = ["UNEXPLAINED_FLOOR", "next_step", "passes_start", "stability_changes", "stamp"]

# A step whose two ends differ in stability with no special point located between them is
# shortened, down to this fraction of the largest step (below it, the change is accepted as it is).
UNEXPLAINED_FLOOR = 1e-3


def stamp(caps, q: Point):
    """The point's stability and the problem's checks, computed once, when the point joins the branch."""
    if q.eigenvalues is None:
        q.eigenvalues = np.asarray(caps.eigenvalues(q.u[:-1], q.u[-1], q.jac), dtype=complex)
        q.diagnostics = caps.diagnostics(q.u[:-1], q.u[-1])


def stability_changes(caps, a: Point, b: Point) -> bool:
    """Whether a and b differ in stability (b stamped now; it would be on joining the branch).
    With no special point located between them, two events fell in one step (a pair of
    multipliers meeting on the real axis and crossing the unit circle, on a branch of (8): no
    test changes sign over the step) and a shorter step separates them."""
    if not caps.has_stability:
        return False
    stamp(caps, b)
    return bool(caps.is_stable(a.eigenvalues)) != bool(caps.is_stable(b.eigenvalues))


def next_step(h, iterations, angle, opts):
    """Grow after an easy correction, shrink after a slow one, and keep the turn per step near
    ``max_angle``."""
    h = min(h * opts.growth, opts.step_max) if iterations <= 3 else (h * 0.6 if iterations >= 6 else h)
    if angle > opts.max_angle:
        h *= opts.max_angle / angle
    return max(h, opts.step_min)


def passes_start(start: Point, ua, ub, h):
    """Whether the step from ua to ub runs through the start point in the start's direction."""
    seg = ub - ua
    w = np.clip((start.u - ua) @ seg / (seg @ seg), 0.0, 1.0)
    return np.linalg.norm(ua + w * seg - start.u) < 0.1 * h and seg @ start.t > 0
