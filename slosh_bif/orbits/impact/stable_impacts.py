"""The least Abar at one sigma with a stable periodic orbit of the vibro-impact model (8) that hits
the walls (eqs. 8, 21): the impact model's critical forcing, as
:mod:`~slosh_bif.orbits.stable_contact` gives (9)'s. On a branch of (8) in Abar it is the lower
end of the stable period-1 orbits with at least one impact a period, one of

- a special point (LP, PD, NS, BP) below which the orbits are unstable or absent;
- a grazing (GR): the impacts stop. Below it the orbit flies free of the walls (loss "none": the
  particle stops hitting them, as at (9)'s contact crossing) or has another number of impacts and
  is unstable (loss "undetermined": a grazing bifurcation has no normal form here);
- the bottom of the range.

A curve of bifurcations bounds stable orbits on one side only; where that side is below the curve,
:func:`stable_impacts_below` finds the orbit there (Newton on the map) and follows its branch down.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import ConvergenceError, newton_solve
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import ImpactBranch, state_at_zero, trace_impact_orbits
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

__all__ = [
    "ImpactLowEnd",
    "impacts_along_bottom",
    "lowest_stable_impacts",
    "stable_impacts_below",
    "stable_impact_orbit_below",
]

BELOW_STEP = 1e-3  # the side below a curve point is probed at Abar (1 - BELOW_STEP), as for (9)
ABOVE = 0.05  # the branch below a curve point is traced up to Abar (1 + ABOVE)
PROBE_ITERATIONS = 12  # Newton steps of a probe (each one evaluation of the exact map)
NEAR_GRAZING = 1e-3  # a piece that starts within this (relative) of a grazing is the orbit beyond it
_BOUNDS = ("LP", "PD", "NS", "BP")


@dataclasses.dataclass(frozen=True)
class ImpactLowEnd:
    """The lower end of the stable period-1 orbits with impacts on a branch of (8) in Abar:
    ``Abar`` (NaN where ``below_range``), ``kind`` (a special point's kind, "GR" at a grazing,
    "unlocated" where stability changes between two points with none located), ``loss`` at a
    grazing ("none" where the orbit below flies free of the walls, else "undetermined"; "" for a
    special point, judged by its normal form), and the ``piece`` and special point ``index`` of
    ``branch`` it lies on (-1 for none); ``symmetric``: the branch is of symmetric orbits, traced
    on the half-period map."""

    Abar: float
    kind: str
    branch: ImpactBranch
    piece: int = -1
    index: int = -1
    loss: str = ""
    below_range: bool = False
    symmetric: bool = False


def lowest_stable_impacts(branch: ImpactBranch, a0: float, symmetric: bool = False) -> ImpactLowEnd | None:
    """The lower end of the stable period-1 orbits with impacts on ``branch`` (of (8), in Abar;
    of symmetric orbits on the half-period map where ``symmetric``), over a range whose bottom is
    ``a0``; None where it has none."""
    best = _lowest_stable(branch)
    if best is None:
        return None
    value, k, i = best
    if value <= a0 + 1e-9 * (1 + abs(a0)):
        return ImpactLowEnd(np.nan, "", branch, k, below_range=True, symmetric=symmetric)
    b = branch.pieces[k].branch
    bounding = [
        (sp.p, j)
        for j, sp in enumerate(b.special)
        # beside point i on either side: a branch of (8) holds its located points among its own
        if sp.kind in _BOUNDS and sp.located and abs(sp.index - i) <= 1 and sp.p <= value
    ]
    if bounding:
        at, j = min(bounding)
        return ImpactLowEnd(float(at), b.special[j].kind, branch, k, j, symmetric=symmetric)
    p = np.asarray(b.p, dtype=float)
    lower = [j for j in (i - 1, i + 1) if 0 <= j < len(p) and p[j] < value]
    grazing = [j for j in lower if _at_grazing(branch, p[j : j + 1])[0]]
    if grazing:
        at = float(p[grazing[0]])
        return ImpactLowEnd(at, "GR", branch, k, loss=_beyond_grazing(branch, at), symmetric=symmetric)
    return ImpactLowEnd(value, "unlocated", branch, k, loss="undetermined", symmetric=symmetric)


def impacts_along_bottom(
    branch: ImpactBranch, at: Params, a0: float, sigma_range, symmetric: bool = False
) -> list:
    """(sigma, good) of each piece of the branch of (8) in sigma at Abar = ``a0`` through the
    lowest stable orbit with impacts of ``branch`` (in Abar at ``at``'s sigma, its stable orbits
    with impacts reaching ``a0``), over ``sigma_range``: ``good`` where its orbits are stable with
    impacts (not at a grazing point); empty where it cannot be traced."""
    found = _lowest_stable(branch)
    if found is None:
        return []
    p, k, i = found
    piece = branch.pieces[k]
    problem = ImpactOrbitProblem(
        at.replace(Abar=p), "Abar", symmetric=symmetric, phase=piece.phase, variant=branch.variant
    )
    try:
        edge = trace_impact_orbits(
            problem.params,
            state_at_zero(problem, piece.branch.x[i], p),
            param="sigma",
            p_min=float(sigma_range[0]),
            p_max=float(sigma_range[1]),
            symmetric=symmetric,
            variant=branch.variant,
        )
    except (ConvergenceError, ValueError):
        return []
    out = []
    for q in edge.pieces:
        s = np.asarray(q.branch.p, dtype=float)
        good = np.asarray(q.branch.stable, dtype=bool) & ~_at_grazing(edge, s) & (q.impacts >= 1)
        out.append((s, good & (q.period_multiple == 1)))
    return out


def _lowest_stable(branch: ImpactBranch):
    """(Abar, piece, index) of the least Abar of the branch's stable period-1 orbits with impacts
    (None for none). A grazing point's own flag counts for nothing: an impact of speed zero."""
    best = None
    for k, piece in enumerate(branch.pieces):
        if piece.impacts < 1 or piece.period_multiple != 1 or not len(piece.branch):
            continue
        p = np.asarray(piece.branch.p, dtype=float)
        stable = np.asarray(piece.branch.stable, dtype=bool) & ~_at_grazing(branch, p)
        if stable.any():
            i = int(np.argmin(np.where(stable, p, np.inf)))
            if best is None or p[i] < best[0]:
                best = (float(p[i]), k, i)
    return best


def _at_grazing(branch: ImpactBranch, p) -> np.ndarray:
    """Whether each parameter value of ``p`` is one of the branch's grazing points (1e-8)."""
    p = np.asarray(p, dtype=float)
    near = np.zeros(p.shape, dtype=bool)
    for g, _, _ in branch.grazing:
        near |= np.abs(p - g) <= 1e-8 * (1 + abs(g))
    return near


def _beyond_grazing(branch: ImpactBranch, at: float) -> str:
    """How the stable orbits with impacts end at the grazing at Abar = ``at``: "none" where a
    piece of the branch without impacts starts or ends there (the particle no longer reaches the
    walls), "undetermined" otherwise."""
    for piece in branch.pieces:
        if piece.impacts == 0 and len(piece.branch):
            ends = np.asarray(piece.branch.p, dtype=float)[[0, -1]]
            if np.any(np.abs(ends - at) <= NEAR_GRAZING * (1 + abs(at))):
                return "none"
    return "undetermined"


def stable_impact_orbit_below(
    params: Params,
    x,
    a0: float,
    *,
    phase: float = 0.0,
    symmetric: bool = False,
    fold: bool = False,
    variant: str = "paper",
):
    """The stable period-1 orbit with impacts just below the curve point (``params.sigma``,
    ``params.Abar``) of (8) whose state on the section tau = ``phase`` is ``x`` (on the
    half-period map where ``symmetric``): (problem, state) from Newton at Abar (1 -
    :data:`BELOW_STEP`) (at a ``fold`` also from x reflected through the first solution: the
    fold's other orbit); None where there is none or that lies below ``a0``."""
    below = params.Abar * (1 - BELOW_STEP)
    if not below > a0:
        return None
    problem = ImpactOrbitProblem(
        params.replace(Abar=below), "Abar", symmetric=symmetric, phase=phase, variant=variant
    )
    x = np.asarray(x, dtype=float)
    first = newton_solve(problem, x, below, tol=1e-12, max_iter=PROBE_ITERATIONS)
    if _stable_with_impacts(problem, first, below):
        return problem, first.x
    if fold and first.converged:
        other = newton_solve(problem, 2 * x - first.x, below, tol=1e-12, max_iter=PROBE_ITERATIONS)
        if _stable_with_impacts(problem, other, below):
            return problem, other.x
    return None


def stable_impacts_below(params: Params, found, a0: float) -> ImpactLowEnd | None:
    """The lower end of the stable orbits with impacts on the branch of (8) in Abar through
    ``found`` ((problem, state) from :func:`stable_impact_orbit_below` below the curve point
    ``params``; None for none), traced down to ``a0``; None where there is none or its branch
    fails."""
    if found is None:
        return None
    problem, x = found
    value = params.Abar
    try:
        branch = trace_impact_orbits(
            problem.params,
            state_at_zero(problem, x, problem.params.Abar),
            param="Abar",
            p_min=a0,
            p_max=value * (1 + ABOVE),
            symmetric=problem.symmetric,
            variant=problem.variant,
        )
    except (ConvergenceError, ValueError):
        return None
    return lowest_stable_impacts(branch, a0, problem.symmetric)


def _stable_with_impacts(problem: ImpactOrbitProblem, run, p) -> bool:
    """Whether the Newton ``run`` at ``p`` converged to a stable orbit with at least one impact."""
    if not run.converged or not problem.in_domain(run.x, p):
        return False
    if not len(problem.evaluate(run.x, p).impacts):
        return False
    return bool(problem.is_stable(problem.eigenvalues(run.x, p)))
