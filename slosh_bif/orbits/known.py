"""Whether an orbit lies on a traced branch of periodic orbits of (9) or on one of its images
under the symmetries of (9) (the mirror (X, w, tau) -> (-X, -w, tau + pi), a shift by 2pi): the
questions a family traced beside others puts to them (:func:`on_known`), and whether their
answers still hold among other branches (:func:`answers_hold`), which lets a scan trace families
side by side and keep the sequential result."""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.branch import polyline_distance
from slosh_bif.orbits.orbit_branch import OrbitBranch, images

__all__ = ["on_branch", "on_known", "answers_hold"]


def on_branch(u, ob: OrbitBranch, tol):
    """Whether the point u = (x, p) lies on a traced branch or on one of its images (mirror,
    shift by 2pi)."""
    b = ob.branch
    copies = np.array([images(ob.problem, x) for x in b.x])  # (points, copies, states)
    if ob.problem.symmetric:  # u is a point of a 2pi problem
        copies = ob.problem.full_states(copies)
    if len(u) != copies.shape[2] + 1:
        return False
    return any(
        polyline_distance(np.column_stack([copies[:, k], b.p]), u) < tol for k in range(copies.shape[1])
    )


def on_known(u, tol, known, asked=None, kind=None) -> bool:
    """Whether the point u = (x, p) lies on a branch of ``known`` (of ``kind`` only, if given) or
    an image of one; the question and its answer are appended to ``asked`` (a list) if given."""
    answer = any(on_branch(u, ob, tol) for ob in known if kind is None or ob.kind == kind)
    if asked is not None:
        asked.append((u, tol, kind, answer))
    return answer


def answers_hold(asked, known) -> bool:
    """Whether every question of ``asked`` (from :func:`on_known`) has the same answer among the
    branches ``known``: then a family traced beside other branches is the one traced beside these,
    up to its branches' names."""
    return all(on_known(u, tol, known, kind=kind) == answer for u, tol, kind, answer in asked)
