"""A curve of orbit bifurcations of the vibro-impact model (8) across its section.

The curve problems solve for the orbit's state on the section tau = ``phase`` of the stroboscopic
map of (8) (eq. 8 with the restitution law 21). Where an impact reaches that section the map is
not smooth and a continuation stops at the domain's edge, though the orbits and the curve go on:
as for a branch (:mod:`slosh_bif.orbits.impact.branches`) the section moves to the middle of the
orbit's longest flight, and the curve is continued from the edge point, in the direction it was
travelling, on the new section. The pieces are then joined in curve order into one branch.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.continuation.branch import Status
from slosh_bif.orbits.impact.branches import quiet_section
from slosh_bif.orbits.impact.problem import SECTION, ImpactOrbitProblem

__all__ = ["MAX_PIECES", "across_sections", "join_pieces", "moved_start", "point_problem"]

MAX_PIECES = 8  # pieces of one curve, the first included


def across_sections(first, branch, new_piece, max_pieces: int = MAX_PIECES) -> list:
    """The curve's pieces in curve order as (problem, branch, reversed): ``first`` (the curve
    problem) and its ``branch`` traced both ways, and at each end where an impact reached the
    section, the pieces beyond it, each traced away from its start (``reversed``: its points run
    towards the first piece, so it is to be read backwards). ``new_piece(problem, point, orient)``
    continues the curve from the END ``point`` of ``problem``'s branch on a moved section (see
    :func:`moved_start`) and returns (problem, branch), or None where it cannot. A piece that
    closes on itself is the whole curve, and is returned alone."""
    before, after = [], []
    for outward, pieces in ((0, before), (-1, after)):
        problem, run, i = first, branch, outward
        while 1 + len(before) + len(after) < max_pieces:
            end = _end_at(run, i)
            if end is None or end.edge != SECTION:
                break
            try:
                found = new_piece(problem, end, _travel(run, i))
            except (ConvergenceError, ValueError):
                found = None
            if found is None:
                break
            problem, run = found
            if any(reason == Status.LOOP.value for _, reason in run.ends):
                return [(problem, run, False)]
            pieces.append((problem, run, outward == 0))
            i = -1  # a piece beyond is traced away from its start: its far end is its last point
    return [*before[::-1], (first, branch, False), *after]


def moved_start(problem, point):
    """(phase, state, params) where the curve ``problem`` continues from its END ``point`` at an
    impact on the section: the section moved to the middle of the orbit's longest flight, the
    orbit's state there, and the parameter set at the point; None where the section does not
    move (no impact over the map's time)."""
    single = point_problem(problem, point.x, point.p)
    phase, state = quiet_section(single, point.x[:4], point.p)
    if abs(phase - problem.orbits.phase) < 1e-9:
        return None
    return phase, state, single.params


def point_problem(problem, u, p) -> ImpactOrbitProblem:
    """The orbits of (8) in the curve's first parameter through the curve ``problem``'s point
    (u, p): its parameter set, section and symmetry."""
    orbits = problem.orbits
    return ImpactOrbitProblem(
        problem.params_at(u, p),
        problem.p1,
        symmetric=orbits.symmetric,
        period_multiple=orbits.period_multiple,
        phase=orbits.phase,
        variant=orbits.variant,
    )


def join_pieces(parts) -> tuple:
    """(branch, measures) of the curve from its pieces in curve order, each (branch, measures,
    reversed): the points of all in order (a reversed piece read backwards), its special points
    renumbered but the END points where two pieces meet, and the ends of the outer pieces."""
    parts = [_read_backwards(b, m) if rev else (b, m) for b, m, rev in parts]
    if len(parts) == 1:
        return parts[0]
    branches = [b for b, _ in parts]
    offsets = np.cumsum([0] + [len(b) for b in branches[:-1]])
    lengths = np.cumsum([0.0] + [b.arclength[-1] if len(b) else 0.0 for b in branches[:-1]])
    last = len(branches) - 1
    special = tuple(
        dataclasses.replace(sp, index=int(sp.index + offsets[k]))
        for k, b in enumerate(branches)
        for sp in b.special
        if not (sp.kind == "END" and ((sp.index == 0 and k > 0) or (sp.index == len(b) - 1 and k < last)))
    )
    ends = (_end_of(branches[0], "backward"), _end_of(branches[-1], "forward"))
    ends = tuple(e for e in ends if e is not None)
    statuses = [b.status for b in (branches[0], branches[-1]) if b.status != "ok"]
    diagnostics = {
        k: np.concatenate([b.diagnostics[k] for b in branches])
        for k in branches[0].diagnostics
        if all(k in b.diagnostics for b in branches)
    }
    branch = dataclasses.replace(
        branches[0],
        p=np.concatenate([b.p for b in branches]),
        x=np.concatenate([b.x for b in branches]),
        stable=np.concatenate([b.stable for b in branches]),
        eigenvalues=np.concatenate([b.eigenvalues for b in branches]),
        newton_iterations=np.concatenate([b.newton_iterations for b in branches]),
        arclength=np.concatenate([b.arclength + s for b, s in zip(branches, lengths)]),
        special=special,
        status=statuses[0] if statuses else "ok",
        message="; ".join(f"{d}: {r}" for d, r in ends) + f" ({len(branches)} pieces: the section moved at "
        "each impact on it)",
        ends=ends,
        diagnostics=diagnostics,
    )
    keys = [k for k in parts[0][1] if all(k in m for _, m in parts)]
    return branch, {k: np.concatenate([m[k] for _, m in parts]) for k in keys}


def _end_at(branch, i: int):
    """The END special point at point ``i`` (0 or -1) of the branch, or None."""
    index = i % len(branch) if len(branch) else -1
    return next((sp for sp in branch.special if sp.kind == "END" and sp.index == index), None)


def _travel(branch, i: int) -> np.ndarray:
    """The direction the curve runs out through its end point ``i`` (0 or -1): in the curve's
    parameters and extra unknowns only (the state's part is on the old section), zero elsewhere."""
    u = np.column_stack([branch.x, branch.p])
    step = u[0] - u[1] if i == 0 else u[-1] - u[-2]
    step[:4] = 0.0
    return step


def _end_of(branch, direction: str):
    """(direction, reason) of the branch's end that way: a piece traced one way has one end."""
    reasons = dict(branch.ends)
    if direction in reasons:
        return direction, reasons[direction]
    return (direction, next(iter(reasons.values()))) if len(reasons) == 1 else None


def _read_backwards(branch, measures) -> tuple:
    """A one-direction piece with its points in the opposite order."""
    n = len(branch)
    total = branch.arclength[-1] if n else 0.0
    flipped = dataclasses.replace(
        branch,
        p=branch.p[::-1].copy(),
        x=branch.x[::-1].copy(),
        stable=branch.stable[::-1].copy(),
        eigenvalues=branch.eigenvalues[::-1].copy(),
        newton_iterations=branch.newton_iterations[::-1].copy(),
        arclength=(total - branch.arclength)[::-1].copy(),
        special=tuple(
            dataclasses.replace(sp, index=n - 1 - sp.index)
            for sp in sorted(branch.special, key=lambda s: -s.index)
        ),
        diagnostics={k: v[::-1].copy() for k, v in branch.diagnostics.items()},
    )
    return flipped, {k: np.asarray(v)[::-1].copy() for k, v in measures.items()}
