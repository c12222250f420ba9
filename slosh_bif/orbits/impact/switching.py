"""Branch switching for periodic orbits of the vibro-impact model (8), eq. (8) with (21): the
asymmetric orbits born at the symmetry-breaking pitchforks of its symmetric ones, and the orbits of
twice the period born at the period doublings of orbits of the full map.

A symmetric orbit y(tau + pi) = -y(tau) is a fixed point of the half-period map G = -phi_pi, and
its pitchfork is G's multiplier -1: a regular zero of a test function there, located to the
corrector's tolerance on a branch traced with ``symmetric=True``. On the full 2pi map the same
point is a simple branch point, and :func:`~slosh_bif.continuation.switch_branch` from the exactly
located point takes the other direction of the two-dimensional null space (from the full map's
own bordered-determinant test the point is known only to the corrector's reach, too coarse for
that direction: as for (9), whose pitchforks are refined on the half-period map). The asymmetric
branch is then traced across sections and grazings like any other (its mirror image is the same
family, found by going through the pitchfork).

From the other side, a located branch point of an asymmetric branch is where it meets its
symmetric parent: switching there on the full map gives a symmetric orbit (checked on the
half-period map), whose branch is then traced on the half-period map (:func:`symmetric_branch`).

A period doubling (multiplier -1 of the map over m forcing periods) is a branch point of the map
over 2m periods, whose fixed points include the parent's: switching there on the doubled map from
the located point takes the new direction, and a point that is not a fixed point of the parent's
map is on the doubled branch.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import ContinuationOptions, ConvergenceError, newton_solve, switch_branch
from slosh_bif.continuation.branch import BRANCH_POINT, FOLD, PERIOD_DOUBLING
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import ImpactBranch, trace_impact_orbits
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

__all__ = ["is_symmetric", "asymmetric_branches", "doubled_branches", "symmetric_branch"]

# Steps onto the new branch: a few short ones, so that the start of the traced branch lies on it
# and clear of the pitchfork (where the full map's Jacobian is singular).
SWITCH_OPTIONS = ContinuationOptions(
    step=0.005, step_max=0.02, tol=1e-10, max_steps=4, detect_branch_points=False
)


def is_symmetric(params: Params, x, tol: float = 1e-8, variant: str = "paper") -> bool:
    """Whether the orbit through x (its state at tau = 0) is symmetric: G(x) = x on the half-period map."""
    half = ImpactOrbitProblem(params, "sigma", symmetric=True, variant=variant)
    return bool(
        np.linalg.norm(half.residual(np.asarray(x, dtype=float), params.sigma))
        <= tol * (1 + np.linalg.norm(x))
    )


def asymmetric_branches(
    params: Params,
    symmetric: ImpactBranch,
    *,
    p_min: float,
    p_max: float,
    options: ContinuationOptions | None = None,
    max_branches: int = 4,
    known: tuple = (),
    say=None,
) -> list:
    """(origin, ImpactBranch) of the asymmetric branch born at each located pitchfork of the
    ``symmetric`` branch (traced on the half-period map), each family once: a pitchfork that an
    earlier asymmetric branch (or one of the ``known`` ones) passes through is not switched at
    again. A switch whose start Newton cannot settle is passed over, told to ``say``."""
    param = symmetric.param
    found = []
    for piece in symmetric.pieces:
        for sp in piece.branch.special:
            if sp.kind != BRANCH_POINT or not sp.located or len(found) >= max_branches:
                continue
            if any(_passes_through(branch, sp.p) for branch in [b for _, b in found] + list(known)):
                continue
            start = _switched_start(params, param, piece.phase, sp, p_min, p_max, variant=symmetric.variant)
            if start is None:
                continue
            x0, p = start
            origin = f"BP at {param} = {sp.p:.6g} on the symmetric branch"
            branch = _traced(
                say,
                origin,
                params.replace(**{param: p}),
                x0,
                param=param,
                p_min=p_min,
                p_max=p_max,
                options=options,
                variant=symmetric.variant,
            )
            if branch is not None:
                found.append((origin, branch))
    return found


def symmetric_branch(
    params: Params,
    asymmetric: ImpactBranch,
    *,
    p_min: float,
    p_max: float,
    options: ContinuationOptions | None = None,
    say=None,
):
    """(origin, ImpactBranch) of the symmetric branch that the asymmetric branch ``asymmetric``
    meets at its first located branch point where switching gives a symmetric orbit (traced on the
    half-period map), or None."""
    param = asymmetric.param
    for piece in asymmetric.pieces:
        if piece.period_multiple != 1:
            continue
        for sp in piece.branch.special:
            if sp.kind != BRANCH_POINT or not sp.located:
                continue
            variant = asymmetric.variant
            # At the pitchfork the asymmetric orbit is the symmetric one: Newton on the half-period
            # map from the branch point itself (regular there: G's multiplier is -1) needs no
            # switching, which a branch point located only to the corrector's reach (it coincides
            # with the asymmetric branch's fold) can send astray.
            run, at = _symmetric_at(params, param, piece.phase, sp, variant), None
            if run is not None and run.converged:
                at = params.replace(**{param: sp.p})
            else:
                start = _switched_start(params, param, piece.phase, sp, p_min, p_max, variant=variant)
                if start is None:
                    continue
                x0, p = start
                at = params.replace(**{param: p})
                half = ImpactOrbitProblem(at, param, symmetric=True, variant=variant)
                run = newton_solve(half, x0, p, tol=1e-12)
            if not (run.converged and is_symmetric(at, run.x, variant=variant)):
                continue
            origin = f"BP at {param} = {sp.p:.6g} on the asymmetric branch"
            branch = _traced(
                say,
                origin,
                at,
                run.x,
                param=param,
                p_min=p_min,
                p_max=p_max,
                options=options,
                symmetric=True,
                variant=variant,
            )
            if branch is not None:
                return origin, branch
    return None


def doubled_branches(
    params: Params,
    parent: ImpactBranch,
    *,
    p_min: float,
    p_max: float,
    options: ContinuationOptions | None = None,
    max_branches: int = 2,
    say=None,
) -> list:
    """(origin, ImpactBranch) of the branch of twice the period born at each located period
    doubling of ``parent`` (orbits of the full map), each family once: a period doubling that an
    earlier doubled branch passes through (as its branch point) is not switched at again."""
    param = parent.param
    found = []
    for piece in parent.pieces:
        for sp in piece.branch.special:
            if sp.kind != PERIOD_DOUBLING or not sp.located or len(found) >= max_branches:
                continue
            if any(_passes_through(branch, sp.p, (BRANCH_POINT, FOLD)) for _, branch in found):
                continue
            start = _doubled_start(params, param, piece, sp, p_min, p_max, parent.variant)
            if start is None:
                continue
            x0, p = start
            origin = f"PD at {param} = {sp.p:.6g}"
            branch = _traced(
                say,
                origin,
                params.replace(**{param: p}),
                x0,
                param=param,
                p_min=p_min,
                p_max=p_max,
                options=options,
                period_multiple=2 * piece.period_multiple,
                variant=parent.variant,
            )
            if branch is not None:
                found.append((origin, branch))
    return found


def _traced(say, origin, params, x0, **trace):
    """The branch traced from a switched start, or None where Newton settles no orbit there (a
    start near a branch point whose new direction is barely resolved), told to ``say``."""
    try:
        return trace_impact_orbits(params, x0, **trace)
    except ConvergenceError as err:
        if say is not None:
            say(f"no branch switched at the {origin}: {err}")
        return None


def _doubled_start(params, param, piece, sp, p_min, p_max, variant):
    """(state at tau = 0, p) of a point of the doubled branch a few short steps from the period
    doubling ``sp`` of ``piece``, or None when switching finds no new branch (or only the parent's
    orbits, which are fixed points of the doubled map too)."""
    start = _switched_start(
        params, param, piece.phase, sp, p_min, p_max, multiple=2 * piece.period_multiple, variant=variant
    )
    if start is None:
        return None
    single = ImpactOrbitProblem(params, param, period_multiple=piece.period_multiple, variant=variant)
    y, p = start
    return None if np.linalg.norm(single.residual(y, p)) <= 1e-6 * (1 + np.linalg.norm(y)) else start


def _switched_start(params, param, phase, sp, p_min, p_max, multiple=1, variant="paper"):
    """(state at tau = 0, p) of a point of the new branch a few short steps from the branch point
    ``sp`` of the map over ``multiple`` forcing periods (a pitchfork of the half-period map on the
    full one; a period doubling on the doubled one), or None when switching finds no new branch."""
    probe = ImpactOrbitProblem(params, param, phase=phase, period_multiple=multiple, variant=variant)
    full = probe.replace(impacts=len(probe.evaluate(sp.x, sp.p).impacts))
    try:
        new = switch_branch(
            full,
            sp,
            param=param,
            options=dataclasses.replace(SWITCH_OPTIONS, p_min=p_min, p_max=p_max),
            along=sp.tangent,
        )
    except ConvergenceError:
        return None
    p = float(new.p[-1])
    return _at_zero(full, new.x[-1], p, phase), p


def _at_zero(problem, x, p, phase):
    """The state at tau = 0 of the orbit through x at the section ``phase``: carried on to tau = 2pi."""
    if phase <= 0:
        return np.asarray(x, dtype=float)
    flow = problem.flow_at(p)
    return flow.run(x, phase, 2 * np.pi, stick_speed=1e-9, max_impacts=10_000)[1][:, -1]


def _symmetric_at(params, param, phase, sp, variant):
    """Newton on the half-period map at the branch point's parameter from its orbit (its state at
    the section ``phase`` carried on to tau = 0), or None when that state cannot be had."""
    at = params.replace(**{param: sp.p})
    probe = ImpactOrbitProblem(at, param, phase=phase, variant=variant)
    try:
        y = _at_zero(probe, sp.x, sp.p, phase)
    except (ValueError, RuntimeError):
        return None
    half = ImpactOrbitProblem(at, param, symmetric=True, variant=variant)
    return newton_solve(half, np.asarray(y, dtype=float), sp.p, tol=1e-12)


def _passes_through(branch: ImpactBranch, p: float, kinds=(BRANCH_POINT,)) -> bool:
    """Whether a switched branch has a special point of ``kinds`` at ``p`` (it reaches this
    pitchfork or period doubling too). A doubled branch is born at a period doubling as a fold in
    the parameter (p - p_PD goes as the square of the distance from the parent), located as
    exactly as the doubling itself; its branch point there is found only to the tracer's step."""
    return any(
        s.kind in kinds and abs(s.p - p) < 1e-4 * (1 + abs(p))
        for piece in branch.pieces
        for s in piece.branch.special
    )
