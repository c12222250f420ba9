"""The first loss of stability of a stable orbit of (9) continued in one parameter.

For ``param="Abar"`` this is the full model's counterpart of the slow flow's critical forcing
Abar_b of (46), at one sigma.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import (
    Branch,
    ContinuationOptions,
    ConvergenceError,
    continuation,
)
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import SHOOTING_OPTIONS
from slosh_bif.orbits.orbit_tools import orbit_at
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = ["StabilityLoss", "loss_of_stability"]


@dataclasses.dataclass(frozen=True)
class StabilityLoss:
    """Where a stable orbit, continued in ``param`` toward ``p_stop``, stops being stable.

    p : the parameter value (None if it stays stable up to p_stop); kind : the special point
    there (LP, BP, PD, NS) or "" when the change is between two points without one; a fold met
    before any change of stability counts too (the orbit ends there); branch : the continuation run.
    """

    param: str
    p: float | None
    kind: str
    branch: Branch


def loss_of_stability(
    params: Params,
    y0,
    *,
    param: str = "Abar",
    p_stop: float = 0.0,
    segments: int = 4,
    options: ContinuationOptions | None = None,
) -> StabilityLoss:
    """Continue the stable 2pi-orbit through ``y0`` (at the value of ``param`` in ``params``)
    toward ``p_stop`` and report the first loss of stability (a fold, a branch point, a period
    doubling or a torus): for ``param="Abar"`` the full model's counterpart of the critical
    forcing, the least forcing down to which this resonant orbit stays stable."""
    p0 = float(getattr(params, param))
    problem = ShootingProblem(params, param, segments=segments)
    start = orbit_at(problem, problem.initial_states(y0), p0)
    if not (start.converged and start.stable):
        raise ConvergenceError(f"no stable orbit near the start at {param} = {p0}: {start.message}")
    lo, hi = sorted((p0, float(p_stop)))
    opts = dataclasses.replace(
        options or SHOOTING_OPTIONS, p_min=lo, p_max=hi, direction="backward" if p_stop < p0 else "forward"
    )
    branch = continuation(problem, problem.initial_states(start.y0), p0, param=param, options=opts)
    # One direction was run, so the start is one end of the branch (which end depends on the
    # orientation of the stored branch): walk from it.
    x_start = problem.initial_states(start.y0)
    from_start = np.linalg.norm(branch.x[0] - x_start) + abs(branch.p[0] - p0) <= np.linalg.norm(
        branch.x[-1] - x_start
    ) + abs(branch.p[-1] - p0)
    order = np.arange(len(branch)) if from_start else np.arange(len(branch))[::-1]
    rank = np.empty(len(branch), dtype=int)
    rank[order] = np.arange(len(branch))
    # A fold ends the orbit's existence on this side even where the stability test does not flip
    # (the Fig. 13 set at sigma = -2 folds at Abar = 0.9745 together with a branch point).
    folds = sorted((rank[s.index], s) for s in branch.special if s.kind == "LP")
    unstable = np.flatnonzero(~branch.stable[order])
    if folds and (unstable.size == 0 or folds[0][0] < unstable[0]):
        return StabilityLoss(param, float(folds[0][1].p), "LP", branch)
    if unstable.size == 0:
        return StabilityLoss(param, None, "", branch)
    i, j = int(order[unstable[0] - 1]), int(order[unstable[0]])  # last stable, first unstable point
    near = [
        s for s in branch.special if s.kind in ("LP", "BP", "PD", "NS") and min(i, j) <= s.index < max(i, j)
    ]
    if near:
        return StabilityLoss(param, float(near[0].p), near[0].kind, branch)
    return StabilityLoss(param, float(0.5 * (branch.p[i] + branch.p[j])), "", branch)
