"""The symmetry-breaking pitchforks of a symmetric branch of (9), located as regular zeros.

On the 2pi problem a pitchfork of symmetric orbits is a branch point: the bordered Jacobian is
singular there, the corrector fails near it, and the engine can bracket it only to a step (Fig. 10
set, Abar = 2.745: to 4e-4 in sigma). A symmetric orbit is a fixed point of the half-period map
G(x) = -phi_pi(x), and at the pitchfork phi_pi has the multiplier +1 (G's -1): the minimally
augmented system of :class:`~slosh_bif.orbits.codim2.PitchforkCurveProblem` at the
branch's parameter, with the other parameter held, is a regular system in (half-period states,
parameter). Newton on it from the engine's point gives the pitchfork to the corrector's
tolerance.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import newton_solve
from slosh_bif.continuation.branch import BRANCH_POINT, Branch
from slosh_bif.orbits.codim2.multiplier_curves import PitchforkCurveProblem
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = ["refine_pitchforks"]


def refine_pitchforks(problem: ShootingProblem, branch: Branch, *, tol: float = 1e-11) -> Branch:
    """``branch`` (of symmetric period-1 orbits of ``problem``, in an even number of arcs) with each
    branch point replaced by the zero of the half-period map's pitchfork condition, where Newton
    finds it inside the point's bracket; other points, and any Newton does not reach, unchanged."""
    if problem.period_multiple != 1 or problem.segments % 2:
        return branch
    # The held parameter only has to differ from the branch's; (sigma, Abar) takes the dedicated kernel.
    other = "Abar" if problem.param == "sigma" else "sigma"
    special = tuple(
        _refined(problem, sp, other, tol) if sp.kind == BRANCH_POINT else sp for sp in branch.special
    )
    return dataclasses.replace(branch, special=special)


def _refined(problem: ShootingProblem, sp, other: str, tol: float):
    half = problem.segments // 2
    at = problem.params_at(sp.p)
    condition = PitchforkCurveProblem(
        at,
        p1=other,
        p2=problem.param,
        segments=half,
        rtol=problem.rtol,
        atol=problem.atol,
        backend=problem.backend,
    )  # no box: the branch's box bounds its parameter, which is p2 here
    u0 = np.append(sp.x[: 4 * half], sp.p)
    held = float(getattr(at, other))
    try:
        condition.init_borders(u0, held)
        result = newton_solve(condition, u0, held, tol=tol)
    except (np.linalg.LinAlgError, ValueError):
        return sp
    lo, hi = min(sp.bracket), max(sp.bracket)
    p = float(result.x[-1])
    if not (result.converged and lo - 1e-9 <= p <= hi + 1e-9):
        return sp
    states = result.x[:-1]
    x = np.concatenate([states, -states])  # the symmetric orbit: y(tau + pi) = -y(tau)
    note = (
        f" (refined on the half-period map, phi_pi's multiplier +1: moved {abs(p - sp.p):.1e} in "
        f"{problem.param})"
    )
    return dataclasses.replace(
        sp, p=p, x=x, message=sp.message.split(" (located to within")[0] + note, located=True
    )
