"""Whether a branch of the vibro-impact model (8) (eqs. 8, 21), restarted on a moved section, is
back on orbits it has already traced.

A branch of (8) goes on across an impact on its section by moving the section
(:mod:`slosh_bif.orbits.impact.branches`). Where the branch is a closed curve, each lap meets the
section's edge at another point, so the new starts do not repeat one another: each lap's start
lies inside a piece of an earlier lap, on another section. The test here carries the start's orbit
to that piece's section, and asks whether Newton at the same parameter, from the piece's own chord
there, lands on it: a regular point of a solution curve lies on one curve only, so the branch goes
on to retrace that piece.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.orbits.impact.parents import SAME_ORBIT
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

__all__ = ["state_at_phase", "retraced_piece"]

CHORD_REACH = 0.25  # the chord's guess is trusted within this fraction of its segment's length


def state_at_phase(problem: ImpactOrbitProblem, x, p, target: float = 0.0):
    """The state on the section tau = ``target`` (modulo the map's period) of the orbit through
    x on the problem's section: the flow of (8) forward to the next such tau, mirrored once per
    half period for a symmetric orbit."""
    x = np.asarray(x, dtype=float)
    periods = int(np.ceil((problem.phase - target) / problem.period - 1e-12))
    end = target + periods * problem.period
    if abs(end - problem.phase) <= 1e-12 * (1 + abs(end)):
        return x.copy()
    _, y, _, code = problem.flow_at(p).run(x, problem.phase, end, stick_speed=1e-9, max_impacts=10_000)
    if code != 0:
        raise ValueError(
            f"the orbit of (8) cannot be followed from its section to tau = {end:g} (code {code})"
        )
    return y[:, -1] * (problem.closing**periods)


def retraced_piece(problem: ImpactOrbitProblem, x, p, pieces) -> int | None:
    """The index of the first of ``pieces`` (:class:`~slosh_bif.orbits.impact.branches.ImpactPiece`
    of the same branch) that holds the orbit through x at ``p`` on ``problem``'s section, or its
    mirror image y(tau + pi) -> -y (the same family, for a problem that is not symmetric
    already); None for none."""
    x = np.asarray(x, dtype=float)
    for k, piece in enumerate(pieces):
        if piece.impacts != problem.impacts or piece.period_multiple != problem.period_multiple:
            continue
        if not _spans(piece.branch.p, p):
            continue
        on_piece = problem.replace(phase=piece.phase, impacts=piece.impacts)
        shifts = (0.0,) if problem.symmetric else (0.0, np.pi)
        for shift in shifts:
            try:
                y = state_at_phase(problem, x, p, piece.phase - shift)
            except ValueError:
                continue
            if _on_piece(on_piece, piece.branch, -y if shift else y, p):
                return k
    return None


def _spans(ps, p) -> bool:
    ps = np.asarray(ps, dtype=float)
    return len(ps) > 1 and ps.min() <= p <= ps.max()


def _on_piece(problem: ImpactOrbitProblem, branch, y, p) -> bool:
    """Whether Newton at ``p`` from a chord of ``branch`` that spans p, near y, converges to y."""
    ps = np.asarray(branch.p, dtype=float)
    xs = np.asarray(branch.x, dtype=float)
    for i in np.flatnonzero((np.minimum(ps[:-1], ps[1:]) <= p) & (p <= np.maximum(ps[:-1], ps[1:]))):
        if ps[i] == ps[i + 1]:
            continue
        t = (p - ps[i]) / (ps[i + 1] - ps[i])
        guess = xs[i] + t * (xs[i + 1] - xs[i])
        length = float(np.hypot(np.linalg.norm(xs[i + 1] - xs[i]), ps[i + 1] - ps[i]))
        if np.linalg.norm(guess - y) > CHORD_REACH * length + SAME_ORBIT:
            continue
        run = newton_solve(problem, guess, p, tol=1e-12, max_iter=8)
        if run.converged and np.linalg.norm(run.x - y) <= SAME_ORBIT * (1 + np.linalg.norm(y)):
            return True
    return False
