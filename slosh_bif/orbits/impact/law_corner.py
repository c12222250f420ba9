"""The corner of the corrected impact model's map where an impact's speed crosses the measured
law's least speed v_min (:mod:`slosh_bif.flows.impact.band`): below it kappa and D are held at
their values there, so the map is continuous but its derivatives jump, and a branch of orbits
reaching it has a corner: its continuation stalls there with vanishing steps (a branch whose slow
impact reaches v_min often turns back in the parameter at that very point, a fold with a
corner). The branch goes on beyond the corner on the other side of v_min, along the tangent of
that side's map, and is continued from there.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.continuation.branch import END
from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.model.restitution.wall import AT_CORNER

__all__ = [
    "CORNER_STEPS",
    "slowest_impact",
    "at_the_laws_corner",
    "corner_message",
    "across_the_corner",
    "corner_sides",
    "without_corner_points",
]

CORNER_STEPS = (1e-6, 1e-5, 1e-4)  # steps along the tangent from the corner to the branch beyond
_PAST = 1e-9  # a point beyond the corner: its slowest impact this far (relative) on the other side


def slowest_impact(problem, x, p) -> float:
    """The smallest impact speed over the orbit through x at p (NaN without impacts or a map)."""
    speeds = _speeds(problem, x, p)
    return math.nan if speeds is None or not len(speeds) else float(speeds.min())


def at_the_laws_corner(problem, x, p) -> bool:
    """Whether the orbit through x at p has an impact at the measured law's least speed (never for
    (8), whose law (21) is smooth)."""
    if problem.variant == "paper":
        return False
    v_min = problem.flow_at(p).wall.v_min
    return abs(slowest_impact(problem, x, p) - v_min) <= AT_CORNER * v_min


def without_corner_points(problem, branch):
    """``branch`` without the special points its tests located at the law's corner: a fold test's
    or a multiplier's sign change across the corner is the jump of the map's derivatives there, no
    bifurcation of a smooth map (a chart's fold curve cannot start from it: no multiplier is at
    1), so it is not reported as one. Its END points stay."""
    if problem.variant == "paper":
        return branch
    keep = tuple(s for s in branch.special if s.kind == END or not at_the_laws_corner(problem, s.x, s.p))
    return branch if len(keep) == len(branch.special) else dataclasses.replace(branch, special=keep)


def corner_message(problem, p) -> str:
    """Why a run ended at the corner where no orbit was found beyond it (appended to its END's)."""
    v_min = problem.flow_at(p).wall.v_min
    return (
        f": an impact there is at the measured law's least speed v = {v_min:g}, below which the law is "
        "held constant, so the map has a corner there; no orbit found beyond it"
    )


def across_the_corner(problem, branch, end, p_range: tuple, previous=None):
    """(x, p, sign) of an orbit beyond the corner the run ``branch`` stalled at (its END point
    ``end``), ``sign`` the parameter's direction away from the corner, or None where none is found
    inside ``p_range``; ``previous``: (problem, branch) of the piece before the run, whose points
    tell the side the corner was reached from where the run's own are all at it. The branch beyond
    leaves the corner along the null vector of the map's [F_x, F_p] on the other side of v_min (the
    Jacobian at the corner's orbit moved a hair across, along the speeds' gradients by
    differences), oriented so that the speeds, functions of the state and the parameter, move to
    that side: Newton at fixed parameter from steps of :data:`CORNER_STEPS` along it, kept where
    a speed at the corner lies on that side. Where several impacts are at the corner at once (a
    mirror pair's), the branch may take any of them across: the slowest alone first (the others
    kept on their side), then each of the others alone, then all."""
    x_end, p_end = np.asarray(end.x, dtype=float), float(end.p)
    v_min = problem.flow_at(p_end).wall.v_min
    before = _came_from(problem, branch, end, v_min)
    if before is None and previous is not None:
        before = _nearest_clear(*previous, end.p, v_min)
    if before is None:
        return None
    other = -1.0 if before > v_min else 1.0  # the side of v_min beyond the corner
    speeds, gradients = _speed_gradients(problem, x_end, p_end)
    if speeds is None or not np.all(np.isfinite(gradients)):
        return None
    at_corner = np.flatnonzero(np.abs(speeds - v_min) <= 1e-4 * v_min)
    if not len(at_corner):
        return None
    order = [int(at_corner[np.argmin(speeds[at_corner])])]
    order += [int(i) for i in at_corner if i != order[0]]
    subsets = [[i] for i in order] + ([list(order)] if len(order) > 1 else [])
    for crossing in subsets:
        found = _across(problem, x_end, p_end, speeds, gradients, crossing, other, v_min, p_range)
        if found is not None:
            return found
    return None


def _across(problem, x_end, p_end, speeds, gradients, crossing, other, v_min, p_range):
    """The orbit beyond the corner with the impacts ``crossing`` taken to the side ``other`` of
    v_min and the corner's other impacts kept where they are, or None."""
    keep = [i for i in range(len(speeds)) if i not in crossing and abs(speeds[i] - v_min) <= 1e-4 * v_min]
    rows_at = crossing + keep
    G = gradients[rows_at, :4]
    if not np.linalg.matrix_rank(G) == len(rows_at):
        return None
    target = np.array(
        [v_min * (1 + other * 1e-5) for _ in crossing] + [v_min * (1 - other * 1e-5) for _ in keep]
    )
    across = x_end + np.linalg.lstsq(G, target - speeds[rows_at], rcond=None)[0]
    rows = np.column_stack([problem.jacobian(across, p_end), problem.dparam(across, p_end)])
    tangent = np.linalg.svd(rows)[2][-1]
    # the speeds' change along the tangent in x and p both: an orbit's impact speeds move with the
    # parameter too, and where the branch leaves the corner nearly along it, that term decides
    tangent = tangent if other * (gradients[crossing[0]] @ tangent) > 0 else -tangent
    for step in CORNER_STEPS:
        q = p_end + step * tangent[-1]
        if not p_range[0] <= q <= p_range[1]:
            continue
        run = newton_solve(problem, x_end + step * tangent[:4], q, tol=1e-12)
        if not run.converged or not problem.in_domain(run.x, q):
            continue
        beyond = _speeds(problem, run.x, q)
        if beyond is not None and len(beyond) == len(speeds):
            if all(other * (beyond[i] - v_min) > _PAST * v_min for i in crossing):
                return run.x, q, 1.0 if tangent[-1] >= 0 else -1.0
    return None


def _came_from(problem, branch, end, v_min, most: int = 50):
    """The slowest impact speed of the run's nearest point before its END ``end`` clear of v_min
    (by :data:`~slosh_bif.model.restitution.wall.AT_CORNER`), among ``most``: a run that crept up to
    the corner has many points at it (the arrays are in arclength order, a backward run's
    reversed)."""
    back = -1 if end.index > 0 else 1
    steps = range(end.index + back, end.index + back * most, back)
    return _first_clear(problem, branch, [k for k in steps if 0 <= k < len(branch.p)], v_min)


def _nearest_clear(problem, branch, p, v_min, most: int = 50):
    """The slowest impact speed of ``branch``'s point nearest p in the parameter that is clear of
    v_min, among its ``most`` nearest."""
    return _first_clear(problem, branch, np.argsort(np.abs(np.asarray(branch.p) - p))[:most], v_min)


def _first_clear(problem, branch, indices, v_min):
    """The slowest impact speed of the first of ``branch``'s points at ``indices`` clear of v_min
    (None where none is)."""
    for k in indices:
        v = slowest_impact(problem, branch.x[k], branch.p[k])
        if math.isfinite(v) and abs(v - v_min) > AT_CORNER * v_min:
            return v
    return None


def corner_sides(problem, x, p) -> tuple:
    """Which of the orbit's impacts are slower than the law's least speed, in time order."""
    speeds = _speeds(problem, x, p)
    v_min = problem.flow_at(p).wall.v_min
    return () if speeds is None else tuple(bool(v < v_min) for v in speeds)


def _speeds(problem, x, p):
    """The impact speeds over the orbit through x at p, in time order (None without a map)."""
    m = problem.evaluate(np.asarray(x, dtype=float), p)
    return None if m.code != 0 else np.abs(m.impacts[:, 2])


def _speed_gradients(problem, x, p, h: float = 1e-7):
    """(speeds, gradients): the impact speeds at (x, p) and each one's gradient in (x, p) by
    central differences ((None, None) where an impact count changes under the differences)."""
    speeds = _speeds(problem, x, p)
    if speeds is None or not len(speeds):
        return None, None
    gradients = np.empty((len(speeds), 5))
    for i in range(5):
        up, down = np.append(x, p).astype(float), np.append(x, p).astype(float)
        up[i] += h
        down[i] -= h
        a, b = _speeds(problem, up[:4], up[4]), _speeds(problem, down[:4], down[4])
        if a is None or b is None or len(a) != len(speeds) or len(b) != len(speeds):
            return None, None
        gradients[:, i] = (a - b) / (2 * h)
    return speeds, gradients
