"""Curves of orbit bifurcations of the vibro-impact model (8) in two parameters: the fold,
period-doubling, pitchfork and Neimark-Sacker curve classes of (9) on the stroboscopic map of (8)
(:class:`~slosh_bif.orbits.impact.strobe.ImpactStrobe`), with the map's exact Jacobian and
parameter derivatives; the second derivatives that the minimally augmented system needs along
the null vector are central differences of that exact Jacobian.

A curve keeps the number of impacts per period of its start: where that changes (grazing) the
map is not smooth and the curve ends at the domain's edge (its status says so). Where an impact
reaches the section tau = ``phase`` the section moves and the curve goes on
(:mod:`~slosh_bif.orbits.impact.curve_pieces`). The grazing points themselves are continued as curves too
(:func:`trace_grazing_curve`, on :class:`~slosh_bif.orbits.impact.grazing.GrazingCurveProblem`).
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from scipy import linalg

from slosh_bif.continuation import ContinuationOptions, continuation, newton_solve
from slosh_bif.model.params import Params
from slosh_bif.orbits.codim2.coefficients import curve_coefficients
from slosh_bif.orbits.codim2.crossing import corrected_at
from slosh_bif.orbits.codim2.curves import (
    CURVE_PROBLEMS,
    BifurcationCurve,
    continue_curve,
    curve_problem,
    read_box,
    start_multipliers,
    start_params,
)
from slosh_bif.orbits.impact.curve_pieces import across_sections, join_pieces, moved_start, point_problem
from slosh_bif.orbits.impact.grazing import FREE, GrazingCurveProblem
from slosh_bif.orbits.impact.map_derivatives import ImpactMapDerivatives
from slosh_bif.orbits.impact.output import orbit_measures
from slosh_bif.orbits.impact.problem import VARIANT_NAMES, ImpactOrbitProblem
from slosh_bif.orbits.impact.strobe import ImpactStrobe, slow_impacts

__all__ = ["ImpactCurveSeed", "impact_corrected_at", "trace_impact_curve", "trace_grazing_curve"]

GR_START_HALVINGS = 10  # halvings of a start's Newton step that leaves the grazing problem's domain


@dataclasses.dataclass(frozen=True)
class ImpactCurveSeed:
    """Where a curve of (8) starts: the special point of ``kind`` (LP, PD, NS or BP) at ``p`` on a
    branch of orbits of (8) continued in ``branch_param``. ``x``: the orbit's state [X, X', w, w']
    on the section tau = ``phase``; ``symmetric``: the branch is one of symmetric orbits (traced on
    the half-period map, as a BP curve needs); ``impacts``: impacts per map period on the branch
    there (None: taken from the orbit); ``variant``: the impact model the branch is of."""

    kind: str
    x: np.ndarray
    p: float
    branch_param: str = "sigma"
    symmetric: bool = False
    phase: float = 0.0
    impacts: int | None = None
    period_multiple: int = 1
    origin: str = ""
    variant: str = "paper"  # or "corrected": the corrected impact model (ImpactOrbitProblem)


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
    the domain's edge at a grazing or cannot be continued (across an impact on the section, in
    pieces on moved sections, :func:`~.curve_pieces.across_sections`); as
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
    strobe = functools.partial(
        ImpactStrobe,
        sensitivities=(p1, p2),
        symmetric=symmetric,
        period_multiple=seed.period_multiple,
        box=(lo1 - 0.5 * span1, hi1 + 0.5 * span1),
        variant=seed.variant,
    )
    orbits = strobe(at, phase=seed.phase, impacts=impacts)
    start = (
        ImpactOrbitProblem(
            at,
            p1,
            symmetric=symmetric,
            period_multiple=seed.period_multiple,
            phase=seed.phase,
            variant=seed.variant,
        )
        .evaluate(x, getattr(at, p1))
        .impacts
    )
    if orbits.impacts is None:  # the domain holds the start's count
        orbits.impacts = len(start)
    orbits.slow = slow_impacts(start[:, 2], orbits.corner)  # and which side of the law's corner each is on
    mu = start_multipliers(orbits, x, at, kind)
    problem = curve_problem(at, kind, p1, p2, p2_box=(lo2, hi2), orbits=orbits)
    branch = continue_curve(problem, x, mu, at, box, options, callback)

    def new_piece(old, point, orient):
        moved = moved_start(old, point)
        if moved is None:
            return None
        phase, state, at_point = moved
        beyond = strobe(at_point, phase=phase, impacts=old.orbits.impacts, slow=old.orbits.slow)
        mu = start_multipliers(beyond, state, at_point, kind)
        piece = curve_problem(at_point, kind, p1, p2, p2_box=(lo2, hi2), orbits=beyond)
        run = continue_curve(
            piece, state, mu, at_point, box, options, callback, orient=orient, tail=point.x[4:]
        )
        return piece, run

    parts = [
        (*_finished(piece, run, seed.variant), backwards)
        for piece, run, backwards in across_sections(problem, branch, new_piece)
    ]
    joined, measures = join_pieces(parts)
    return BifurcationCurve(kind, p1, p2, joined, measures, seed.origin, seed.period_multiple)


def impact_corrected_at(curve, params: Params, value: float, segment: int, variant: str = "paper"):
    """p2 of the curve of (8) (of the impact model ``variant``) at p1 = ``value``, corrected on the
    curve's own system from the interpolation over its points ``segment`` and ``segment + 1``
    (:func:`~slosh_bif.orbits.codim2.crossing.corrected_at`), with their section, number of
    impacts and the sides of the law's corner the impacts are on held; None where the two points
    lie on different sections or the correction fails."""
    i = int(segment)
    phase = curve["phase"]
    if phase[i] != phase[i + 1]:
        return None
    x = curve.branch.x[i, :4]
    at = params.replace(**{curve.p1: float(curve.branch.p[i]), curve.p2: float(curve.branch.x[i, 4])})
    symmetric = curve.kind == "BP"
    try:
        probe = ImpactOrbitProblem(
            at,
            curve.p1,
            symmetric=symmetric,
            period_multiple=curve.period_multiple,
            phase=float(phase[i]),
            variant=variant,
        )
        impacts = probe.evaluate(x, getattr(at, curve.p1)).impacts
        orbits = ImpactStrobe(
            at,
            sensitivities=(curve.p1, curve.p2),
            symmetric=symmetric,
            period_multiple=curve.period_multiple,
            phase=float(phase[i]),
            impacts=len(impacts),
            variant=variant,
            slow=slow_impacts(impacts[:, 2], probe.flow_at(getattr(at, curve.p1)).slowest_smooth_impact),
        )
    except ValueError:
        return None
    return corrected_at(curve, params, value, i, orbits=orbits)


def _finished(problem, branch, variant) -> tuple:
    """(branch, measures) of one piece of a curve: the normal form's coefficient along it (its
    zeros added to the special points), the orbits' measures and ``phase``, the section its
    points' states are on."""
    phase = problem.orbits.phase
    derivatives = functools.partial(ImpactMapDerivatives, phase=phase, variant=variant)
    branch, coefficients = curve_coefficients(problem, branch, derivatives)
    return branch, {**_measures(problem, branch), **coefficients, "phase": np.full(len(branch), phase)}


def _measures(problem, branch) -> dict:
    """A1, max |X|, max |w| and the slowest impact speed of each point's orbit, and the largest
    multiplier but the critical ones."""
    rows = [orbit_measures(point_problem(problem, u, p), u[:4], p) for u, p in zip(branch.x, branch.p)]
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


def trace_grazing_curve(
    params: Params,
    seed: ImpactCurveSeed,
    *,
    box: dict,
    options: ContinuationOptions | None = None,
    callback=None,
) -> BifurcationCurve:
    """Trace the grazing curve (kind GR) through the grazing point of ``seed`` (a GR point of a
    branch of orbits of (8): ``seed.x`` the orbit's state on its section tau = ``seed.phase``
    there) over ``box`` as :func:`trace_impact_curve` does for the other kinds. The seed is first
    moved onto the grazing exactly (Newton at its p1 on
    :class:`~slosh_bif.orbits.impact.grazing.GrazingCurveProblem`); a seed that is not
    within 1e-4 of a regular grazing (a branch's GR points are located to 1e-9; the margin is for
    seeds given otherwise) is refused with the reason."""
    if seed.kind != "GR":
        raise ValueError(f"a grazing curve starts from a GR point; got kind {seed.kind!r}")
    (p1, (lo1, hi1)), (p2, (lo2, hi2)) = read_box(box)
    at = start_params(params, seed, box)
    probe = ImpactOrbitProblem(
        at,
        p1,
        symmetric=seed.symmetric,
        period_multiple=seed.period_multiple,
        phase=seed.phase,
        variant=seed.variant,
    )
    x = np.asarray(seed.x, dtype=float)
    gap = probe.grazing(x, getattr(at, p1))
    flow = probe.flow_at(getattr(at, p1))
    if not gap.gap < 1e-4:
        raise ValueError(
            f"the start is not a grazing orbit of {VARIANT_NAMES[seed.variant]}: its nearest approach to "
            f"grazing is {gap.gap:.3g}"
        )
    # to the grazing point: the compiled flow to FREE before it, then the flight with the wall
    # ignored (a grazing impact of speed ~0 there would stop the flow as sticking)
    t_g = gap.t
    t_near = max(seed.phase, t_g - FREE)
    y = x
    if t_near > seed.phase:
        _, ys, _, code = flow.run(x, seed.phase, t_near, stick_speed=1e-9, max_impacts=10_000)
        if code != 0:
            raise ValueError(f"the start orbit of (8) cannot be followed to its grazing point (code {code})")
        y = ys[:, -1]
    free = linalg.expm(flow.K * (t_g - t_near))
    y_g = (free @ np.concatenate([y, [np.cos(t_near), np.sin(t_near)]]))[:4]
    span1 = hi1 - lo1
    problem = GrazingCurveProblem(
        at,
        p1,
        p2,
        side=float(np.sign(y_g[2])),
        symmetric=seed.symmetric,
        period_multiple=seed.period_multiple,
        box=(lo1 - 0.5 * span1, hi1 + 0.5 * span1),
        p2_box=(lo2, hi2),
        variant=seed.variant,
        # the other impacts on their sides of the law's corner, as the seed has them (the grazing
        # contact itself, slower than MIN_IMPACT_SPEED where it shows as an impact, is not counted)
        slow=slow_impacts(probe.evaluate(x, getattr(at, p1)).impacts[:, 2], flow.slowest_smooth_impact),
    )
    u0 = np.array([y_g[0], y_g[1], t_g, getattr(at, p2)])
    p1_0 = float(getattr(at, p1))
    # halved back into the domain: beside a second contact near grazing (the seed just across
    # it, say) a full step can flip that contact, though the grazing orbit is within reach
    run = newton_solve(problem, u0, p1_0, tol=1e-11, halvings=GR_START_HALVINGS)
    if not run.converged:
        raise ValueError(f"no grazing orbit of {VARIANT_NAMES[seed.variant]} near the start: {run.message}")
    problem.impacts = len(problem.evaluate(run.x, p1_0)[4])
    if not problem.in_domain(run.x, p1_0):
        raise ValueError(
            "the start's grazing is not a regular one (the particle does not leave the wall inward)"
        )
    opts = dataclasses.replace(options or CURVE_OPTIONS_GR, p_min=lo1, p_max=hi1)
    branch = continuation(problem, run.x, p1_0, param=p1, options=opts, callback=callback)
    return BifurcationCurve(
        "GR", p1, p2, branch, _grazing_measures(problem, branch), seed.origin, seed.period_multiple
    )


# A grazing curve has no test functions; its steps as the other curves' of (8).
CURVE_OPTIONS_GR = ContinuationOptions(
    step=0.05, step_max=0.25, tol=1e-10, max_steps=2000, detect_folds=False, detect_branch_points=False
)


def _grazing_measures(problem: GrazingCurveProblem, branch) -> dict:
    """The measures of :func:`_measures` for each grazing orbit, taken from the end of the map's
    first free stretch (max |w| is 1: the orbit touches the wall)."""
    rows = []
    for u, p in zip(branch.x, branch.p):
        at = problem.params_at(u, p)
        t_start = float(u[2]) + FREE
        single = ImpactOrbitProblem(
            at,
            problem.p1,
            symmetric=problem.symmetric,
            period_multiple=problem.period_multiple,
            phase=t_start,
            variant=problem.variant,
        )
        row = orbit_measures(single, problem.leaving(u, p), p)
        row["max_abs_w"] = max(row["max_abs_w"], problem.level_at(u, p))
        rows.append(row)
    keys = ("A1", "max_abs_X", "max_abs_w", "min_impact_speed")
    out = (
        {key: np.array([r[key] for r in rows]) for key in keys}
        if rows
        else {key: np.array([]) for key in keys}
    )
    out["max_abs_multiplier"] = np.max(np.abs(branch.eigenvalues), axis=1) if len(branch) else np.array([])
    return out
