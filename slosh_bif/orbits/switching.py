"""Switching onto the branches born at a special point of a family's branch of orbits of (9):
the tangent to start along, the problem the new branch lives on (twice the period at a period
doubling, the whole period at a pitchfork of the half-period map), and where a switched branch
meets its parent again (a branch joining two pitchforks, or two period doublings, is traced
once). Used by :func:`~slosh_bif.orbits.families.trace_new_family`.
"""

from __future__ import annotations

import copy

import numpy as np

from slosh_bif.continuation import continuation, switch_branch
from slosh_bif.continuation.branch import BRANCH_POINT, PERIOD_DOUBLING, Branch
from slosh_bif.orbits.orbit_branch import OrbitBranch, images
from slosh_bif.orbits.orbit_tools import is_symmetric, symmetrized
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = [
    "tangent_at",
    "meeting_points",
    "met_at",
    "cut_where_it_rejoins",
    "image_of_settled",
    "point_counter",
    "switched_branch",
    "meets_parent",
    "symmetrized_point",
    "symmetric_parent",
]


def tangent_at(branch: Branch, sp, regular: bool = False):
    """The branch's unit tangent at a special point: the one the engine kept at a regular point
    (a period doubling), else the secant of its neighbours. At a branch point the null space of
    [F_x, F_p] is two-dimensional, so the tangent computed there is not the branch's (with it,
    switching on the Fig. 10 family returned onto the symmetric branch). On the half-period map
    a pitchfork is a regular point, and its tangent is the branch's."""
    if sp.tangent is not None and (sp.kind != BRANCH_POINT or regular):
        return np.asarray(sp.tangent, dtype=float)
    u = np.column_stack([branch.x, branch.p])
    lo, hi = max(sp.index - 1, 0), min(sp.index + 1, len(u) - 1)
    t = u[hi] - u[lo]
    return t / np.linalg.norm(t)


def meeting_points(problem: ShootingProblem, parent: OrbitBranch):
    """(point of ``parent``, its states in ``problem``) where a branch switched off the parent may
    meet it again: its period doublings for a branch of twice its period, else its branch points."""
    doubled = problem.period_multiple == 2 * parent.problem.period_multiple
    kind = PERIOD_DOUBLING if doubled else BRANCH_POINT
    return [
        (q, np.tile(q.x, 2) if doubled else parent.problem.full_states(q.x))
        for q in parent.branch.special
        if q.kind == kind
    ]


def met_at(meeting, kind, x, p):
    """The parent's point in ``meeting`` that a branch point (kind, x, p) of the new branch is, or None."""
    if kind != BRANCH_POINT:
        return None
    for q, xq in meeting:
        if (
            len(xq) == len(x)
            and abs(q.p - p) <= 1e-6 * (1 + abs(q.p))
            and np.linalg.norm(xq - x) <= 1e-4 * (1 + np.linalg.norm(xq))
        ):
            return q
    return None


def cut_where_it_rejoins(new: Branch, problem: ShootingProblem, parent: OrbitBranch, queue: list):
    """Cut a switched branch at the first branch point (past its start) where it meets its parent
    again. A branch joining two pitchforks of the symmetric branch continues past the second as
    the mirror image of what it traced, and a period-2 branch joining two period doublings as
    its own shift by 2pi: nothing new (:func:`switched_branch` stops the trace there). The parent's point
    met there leaves the queue."""
    meeting = meeting_points(problem, parent)
    for sp in new.special:
        q = met_at(meeting, sp.kind, sp.x, sp.p) if sp.index > 1 else None
        if q is not None:
            queue[:] = [(ob, s) for ob, s in queue if s is not q]
            return new.head(sp.index, f"meets the {parent.name} branch again at its {q.kind}"), q
    return new, None


def image_of_settled(parent: OrbitBranch, sp, settled):
    """The ``(branch, point)`` of ``settled`` (the points a family switched at or met again) whose
    orbit is that of the special point ``sp`` of ``parent`` or an image of it under the symmetries
    of (9) (:func:`~slosh_bif.orbits.orbit_branch.images`), of the same kind at the same parameter;
    None if none. A branch traced as a closed loop through both members of a mirror pair meets each
    of its period doublings twice, once on each member, and the pitchfork where the pair meets its
    symmetric parent is a branch point of both: by the symmetry the branch born at the second of
    such points is (an image of) the one born at the first, nothing new."""
    x = parent.problem.full_states(sp.x)  # a symmetric branch's half period made whole
    tol = 1e-4 * (1 + np.linalg.norm(x))
    for ob, q in settled:
        if (q.kind, ob.problem.period_multiple) != (sp.kind, parent.problem.period_multiple) or abs(
            q.p - sp.p
        ) > 1e-6 * (1 + abs(q.p)):
            continue
        copies = [ob.problem.full_states(c) for c in images(ob.problem, q.x)]
        if any(len(c) == len(x) and np.linalg.norm(c - x) <= tol for c in copies):
            return ob, q
    return None


def point_counter(say, name, param):
    """A continuation callback that reports each accepted point of the branch ``name``."""
    count = [0]

    def callback(p, x):
        count[0] += 1
        say(f"{name}: point {count[0]}, {param} = {p:.5f}")

    return callback


def switched_branch(parent: OrbitBranch, sp, param, opts, make_problem, say, own_problem: bool = False):
    """(problem, branch, name or None) switched onto at the special point ``sp`` of ``parent``:
    at a period doubling the 4pi problem (on which the PD is a branch point), at a pitchfork of
    the half-period map the 2pi problem (where it is a branch point), else the parent's.
    ``own_problem``: trace on a copy of the parent's problem (whose integration caches are its
    own), for a trace beside others on the same parent; the parent's is returned all the same."""
    along = tangent_at(parent.branch, sp, regular=parent.problem.symmetric)
    if parent.problem.symmetric:
        problem = make_problem(1)
        x, along = (
            parent.problem.full_states(sp.x),
            np.append(parent.problem.full_states(along[:-1]), along[-1]),
        )
        name = None
    elif sp.kind == PERIOD_DOUBLING:
        multiple = 2 * parent.problem.period_multiple
        problem = make_problem(multiple)
        x, along = np.tile(sp.x, 2), np.append(np.tile(along[:-1], 2), along[-1])
        name = f"period-{multiple}"
    else:
        problem, x, name = parent.problem, sp.x, None
    traced_on = copy.copy(problem) if own_problem and problem is parent.problem else problem
    meeting = meeting_points(problem, parent)
    new = switch_branch(
        traced_on,
        (x, sp.p),
        param=param,
        options=opts,
        along=along,
        callback=point_counter(say, name or "new branch", param),
        stop=lambda kind, x, p, index: index > 1 and met_at(meeting, kind, x, p) is not None,
    )
    return problem, new, name


def meets_parent(parent: OrbitBranch, sp) -> bool:
    """Whether ``sp`` is a branch point of an asymmetric 2pi branch at a symmetric orbit: where the
    pair meets its symmetric parent (the parent's pitchfork)."""
    return sp.kind == BRANCH_POINT and is_symmetric(parent.problem, sp.x)


def symmetrized_point(sp):
    """(x, p) of the branch point ``sp`` of a 2pi problem whose orbit is symmetric to its location's
    accuracy, its states made exactly symmetric (:func:`~.orbit_tools.symmetrized`)."""
    return np.append(symmetrized(sp.x), sp.p)


def symmetric_parent(sp, param, opts, make_problem, say):
    """(problem, branch, "symmetric") of the symmetric orbits through the branch point ``sp`` where
    an asymmetric pair meets its parent (a family started on the pair: the tank example's
    attractor), traced both ways on the half-period map, where the pitchfork is a regular point."""
    problem = make_problem(1, symmetric=True)
    x = symmetrized_point(sp)[: 4 * problem.segments]
    branch = continuation(
        problem, x, sp.p, param=param, options=opts, callback=point_counter(say, "symmetric parent", param)
    )
    return problem, branch, "symmetric"
