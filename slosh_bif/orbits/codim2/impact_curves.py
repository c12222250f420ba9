"""Curves of orbit bifurcations of the vibro-impact model (8) in two parameters: the fold,
period-doubling, pitchfork and Neimark-Sacker curve classes of (9) on the stroboscopic map of (8)
(:class:`~slosh_bif.orbits.codim2.impact_strobe.ImpactStrobe`), with the map's exact Jacobian and
parameter derivatives; the second derivatives that the minimally augmented system needs along
the null vector are central differences of that exact Jacobian.

A curve keeps the number of impacts per period of its start: where that changes (grazing) or an
impact reaches the section tau = ``phase``, the map is not smooth and the curve ends at the
domain's edge (its status says so).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import ContinuationOptions
from slosh_bif.model.params import Params
from slosh_bif.orbits.codim2.curves import (
    CURVE_PROBLEMS,
    BifurcationCurve,
    continue_curve,
    curve_problem,
    read_box,
    start_multipliers,
    start_params,
)
from slosh_bif.orbits.codim2.impact_strobe import ImpactStrobe
from slosh_bif.orbits.impact_orbits import ImpactOrbitProblem
from slosh_bif.orbits.impact_output import orbit_measures

__all__ = ["ImpactCurveSeed", "trace_impact_curve"]


@dataclasses.dataclass(frozen=True)
class ImpactCurveSeed:
    """Where a curve of (8) starts: the special point of ``kind`` (LP, PD, NS or BP) at ``p`` on a
    branch of orbits of (8) continued in ``branch_param``. ``x``: the orbit's state [X, X', w, w']
    on the section tau = ``phase``; ``symmetric``: the branch is one of symmetric orbits (traced on
    the half-period map, as a BP curve needs); ``impacts``: impacts per map period on the branch
    there (None: taken from the orbit)."""

    kind: str
    x: np.ndarray
    p: float
    branch_param: str = "sigma"
    symmetric: bool = False
    phase: float = 0.0
    impacts: int | None = None
    period_multiple: int = 1
    origin: str = ""


def trace_impact_curve(
    params: Params,
    seed: ImpactCurveSeed,
    *,
    box: dict,
    options: ContinuationOptions | None = None,
    callback=None,
) -> BifurcationCurve:
    """Trace the curve of ``seed.kind`` of periodic orbits of (8) through the seed's special point
    over ``box``, ``{p1: (low, high), p2: (low, high)}`` (two parameters of (8): eps, beta,
    gamma, sigma, Abar, lam or chi), in both directions until it leaves the box, closes, reaches
    the domain's edge (grazing, an impact on the section) or cannot be continued; as
    :func:`~slosh_bif.orbits.codim2.curves.trace_curve` does for (9). A fold, period-doubling or
    torus curve from a symmetric branch is traced on the whole-period map, a pitchfork curve on
    the half-period map."""
    kind = seed.kind
    if kind not in CURVE_PROBLEMS:
        raise ValueError(f"kind must be one of {', '.join(CURVE_PROBLEMS)}; got {kind!r}")
    if kind == "BP" and not seed.symmetric:
        raise ValueError("a BP curve starts from a branch of symmetric orbits (seed.symmetric = True)")
    (p1, (lo1, hi1)), (p2, (lo2, hi2)) = read_box(box)
    x = np.asarray(seed.x, dtype=float)
    if x.shape != (4,) or not np.all(np.isfinite(x)):
        raise ValueError(
            f"the start must be the orbit's state on the section, 4 finite numbers; got shape {x.shape}"
        )
    at = start_params(params, seed, box)
    symmetric = kind == "BP"
    impacts = seed.impacts
    if impacts is not None and seed.symmetric and not symmetric:
        impacts *= 2  # the whole period holds the half period's impacts twice
    span1 = hi1 - lo1
    orbits = ImpactStrobe(
        at,
        (p1, p2),
        symmetric=symmetric,
        period_multiple=seed.period_multiple,
        box=(lo1 - 0.5 * span1, hi1 + 0.5 * span1),
        phase=seed.phase,
        impacts=impacts,
    )
    mu = start_multipliers(orbits, x, at, kind)
    if orbits.impacts is None:  # the domain holds the start's count
        orbits.impacts = len(
            ImpactOrbitProblem(
                at, p1, symmetric=symmetric, period_multiple=seed.period_multiple, phase=seed.phase
            )
            .evaluate(x, getattr(at, p1))
            .impacts
        )
    problem = curve_problem(at, kind, p1, p2, p2_box=(lo2, hi2), orbits=orbits)
    branch = continue_curve(problem, x, mu, at, box, options, callback)
    return BifurcationCurve(
        kind, p1, p2, branch, _measures(problem, branch), seed.origin, seed.period_multiple
    )


def _measures(problem, branch) -> dict:
    """A1, max |X|, max |w| and the slowest impact speed of each point's orbit, and the largest
    multiplier but the critical ones."""
    orbits = problem.orbits
    rows = []
    for u, p in zip(branch.x, branch.p):
        at = problem.params_at(u, p)
        single = ImpactOrbitProblem(
            at,
            problem.p1,
            symmetric=orbits.symmetric,
            period_multiple=orbits.period_multiple,
            phase=orbits.phase,
        )
        rows.append(orbit_measures(single, u[:4], p))
    out = (
        {
            key: np.array([r[key] for r in rows])
            for key in ("A1", "max_abs_X", "max_abs_w", "min_impact_speed")
        }
        if rows
        else {}
    )
    critical = 2 if problem.kind == "NS" else 1
    out["max_abs_multiplier"] = (
        np.max(np.abs(branch.eigenvalues[:, critical:]), axis=1) if len(branch) else np.array([])
    )
    return out
