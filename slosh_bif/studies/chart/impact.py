"""The (sigma, Abar) chart of the vibro-impact model (8): the curves where its periodic orbits
fold (LP), double their period (PD), lose stability to a torus (NS), break their symmetry (BP)
or graze the wall (GR: the number of impacts per period changes),
traced in two parameters (:func:`~slosh_bif.orbits.impact.curves.trace_impact_curve`) from
every special point of its branches in sigma (the branch a simulation of (8) settles on and, for a
symmetric one, the asymmetric branches born at its pitchforks, and the cascade born at their
period doublings, within six branches: each branch's curves are of orbits of its period), and the
least forcing Abar_c at which (8) has a stable periodic orbit, read off them as for (9)
(:mod:`slosh_bif.studies.chart.smooth`). The result is a
:class:`~slosh_bif.studies.chart.result.Chart`, written and drawn by the chart's own output functions.

A curve keeps its start's number of impacts per period; it ends at the domain's edge where that
changes (on a grazing curve; the chart does not yet follow a curve across it); where an impact
reaches its section, the section moves and the curve goes on. A grazing curve bounds Abar_c where
its orbits are stable: there the stable orbit with contact exists up to the grazing.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import settled_orbit, state_at_zero, trace_impact_orbits
from slosh_bif.orbits.impact.curves import ImpactCurveSeed, trace_grazing_curve, trace_impact_curve
from slosh_bif.orbits.impact.problem import VARIANT_NAMES, ImpactOrbitProblem
from slosh_bif.orbits.impact.starts import impact_start
from slosh_bif.orbits.impact.strobe import MIN_IMPACT_SPEED
from slosh_bif.orbits.impact.switching import (
    asymmetric_branches,
    doubled_branches,
    is_symmetric,
    symmetric_branch,
)
from slosh_bif.orbits.settings import BRANCHING, BranchingSettings
from slosh_bif.orbits.shooting import MAX_PERIOD_MULTIPLE
from slosh_bif.report.files import Resume
from slosh_bif.slowflow.critical import critical_curve
from slosh_bif.studies.chart.bottom import impact_bottom
from slosh_bif.studies.chart.curves import CurveStart, side_at, trace_curves
from slosh_bif.studies.chart.result import Chart, ChartSettings, check_box, where
from slosh_bif.studies.chart.seeds import regular_points, seed_branching, seed_points, uncovered_points

__all__ = ["impact_chart", "impact_family", "impact_curve_starts", "ImpactFamily", "NamedImpactBranch"]


@dataclasses.dataclass(frozen=True)
class NamedImpactBranch:
    """A branch of orbits of (8) in sigma (:class:`~slosh_bif.orbits.impact.branches.ImpactBranch`),
    its name, and whether it was traced on the half-period map (symmetric orbits)."""

    name: str
    branch: object
    symmetric: bool


@dataclasses.dataclass(frozen=True)
class ImpactFamily:
    """The branches of (8) a chart's curves start from, the primary one first."""

    branches: list


def impact_chart(
    params: Params,
    state0,
    *,
    sigma_range: tuple,
    abar_range: tuple,
    branching: BranchingSettings = BRANCHING,
    settings: ChartSettings | None = None,
    progress=None,
    variant: str = "paper",
    resume: Resume | None = None,
) -> Chart:
    """The chart of (8) over ``sigma_range`` x ``abar_range``: the branch of orbits of (8) through
    the orbit a ``settings.settle``-period simulation from ``state0`` settles on (at the set's
    sigma and Abar; where it settles on none, from the slow flow's motion on a steady state of
    (46) in the box: :func:`~slosh_bif.orbits.impact.starts.impact_start`), the asymmetric
    branches born at its pitchforks (unless ``branching.switch`` is off), the primary branch's
    orbits at ``settings.seeds`` values of sigma continued in Abar (where it does not reach, the
    orbits a simulation settles on there), and the curve through each of their LP, PD, NS and BP
    points (each curve once), on ``settings.workers`` processes; the paper's slow flow's Abar_b
    beside them. ``resume``: the curves of an earlier run with the same settings, and the callback
    that stores each new one (as for :func:`~slosh_bif.studies.chart.smooth.bifurcation_chart`)."""
    check_box(params, sigma_range, abar_range)
    settings, resume = settings or ChartSettings(), resume or Resume()
    (s0, s1), (a0, a1) = sigma_range, abar_range
    say = progress or (lambda message: None)
    started = time.perf_counter()
    try:
        start = impact_start(params, state0, periods=settings.settle, p_range=(s0, s1), variant=variant)
    except ConvergenceError as err:
        raise ConvergenceError(
            f"{err}; the chart's family starts from that orbit: start it at another sigma or Abar "
            "inside the box (--set sigma=S --set Abar=A)"
        ) from None
    say(f"start orbit at sigma = {start.params.sigma:.5g}: {start.found_from}")
    family = impact_family(
        start.params,
        start.x,
        param="sigma",
        p_range=(s0, s1),
        variant=variant,
        # the period-doubling cascade too (each branch's curves of its own period), six branches in all
        branching=dataclasses.replace(branching, max_branches=min(branching.max_branches, 6)),
    )
    say(
        f"orbits of {VARIANT_NAMES[variant]}: {len(family)} branch(es), "
        f"{sum(len(piece.branch) for nb in family for piece in nb.branch.pieces)} points"
    )
    box = {"sigma": (s0, s1), "Abar": (a0, a1)}
    starts = _family_starts(family, params, box)
    # Folds and period doublings met when the forcing falls: the primary branch's orbits at
    # ``settings.seeds`` values of sigma, each continued in Abar over the box with the pairs born
    # at its pitchforks (not the cascades).
    pieces = [piece.branch for piece in family[0].branch.pieces]
    switching = seed_branching(branching)
    seeds_found = []  # (sigma, family in Abar) of each seed: the chart's self-check
    for k, i in seed_points([(b.p, regular_points(b)) for b in pieces], (s0, s1), settings.seeds):
        at, seeds = _seeds_in_abar(family[0], family[0].branch.pieces[k], i, params, (a0, a1), switching)
        starts += _family_starts(seeds, at, box)
        seeds_found.append((float(at.sigma), ImpactFamily(seeds)))
    # Where the primary branch does not reach (an isola, a branch ending in the box): the orbit
    # a simulation settles on at sigmas there, continued in Abar as a seed is.
    for sigma in uncovered_points([b.p for b in pieces], (s0, s1), settings.seeds):
        at = params.replace(sigma=sigma)
        try:
            x = settled_orbit(at, state0, periods=settings.settle, variant=variant)
            seeds = impact_family(at, x, param="Abar", p_range=(a0, a1), branching=switching, variant=variant)
        except (ConvergenceError, ValueError) as err:
            say(
                f"no orbit of {VARIANT_NAMES[variant]} at sigma = {sigma:.4g} (outside the primary "
                f"branch): {err}"
            )
            continue
        starts += _family_starts(seeds, at, box)
        seeds_found.append((float(sigma), ImpactFamily(seeds)))
    bottom = impact_bottom(seeds_found, params, (s0, s1), a0, say)
    tasks = []
    say(f"{len(starts)} special points of {VARIANT_NAMES[variant]} to start curves from, {where(settings)}")
    if resume.done:
        say(f"{len(resume.done)} curves from an earlier run")
    curves, status, failures = trace_curves(
        starts, say, settings.slots, resume.done, resume.keep, executor=settings.executor, tasks=tasks
    )
    slow = None
    try:
        slow = critical_curve(params, s0, s1)
    except (RuntimeError, ValueError) as err:
        say(f"no slow-flow critical curve: {err}")
    return Chart(
        params,
        (s0, s1),
        (a0, a1),
        ImpactFamily(family),
        curves,
        slow,
        time.perf_counter() - started,
        status,
        "Abar",
        failures,
        orbits=VARIANT_NAMES[variant],
        tasks=tuple(tasks),
        seeds=tuple(seeds_found),
        bottom=bottom,
    )


def impact_family(
    params: Params,
    x0,
    *,
    param: str,
    p_range: tuple,
    branching: BranchingSettings = BRANCHING,
    options=None,
    say=None,
    variant: str = "paper",
) -> list:
    """The branch of orbits of (8) (``variant`` "paper" or "corrected") through x0 (its state at tau = 0) over
    ``p_range`` of ``param`` (a symmetric one on the half-period map) and, unless ``branching.switch`` is off,
    the asymmetric branches born at its pitchforks (for an asymmetric start, first the symmetric
    branch it meets at its own branch point, then that one's other pitchforks') and (with
    ``branching.doublings``) the branches of
    twice the period born at the period doublings of its non-symmetric branches (a cascade followed
    to period 8, ``branching.max_branches`` branches in all), as
    :class:`NamedImpactBranch` (the first one first); ``say(message)`` hears of each switched
    branch."""
    lo, hi = p_range
    # a symmetric start is continued on the half-period map, where its pitchforks are regular points
    symmetric = is_symmetric(params, x0, variant=variant)
    primary = trace_impact_orbits(
        params, x0, param=param, p_min=lo, p_max=hi, options=options, symmetric=symmetric, variant=variant
    )
    family = [NamedImpactBranch("symmetric" if symmetric else "primary", primary, symmetric)]
    known = ()
    if not symmetric and branching.switch:  # the symmetric parent, met at the primary's pitchfork
        met = symmetric_branch(params, primary, p_min=lo, p_max=hi, options=options, say=say)
        if met is not None:
            family.append(NamedImpactBranch("symmetric", met[1], True))
            known = (primary,)
            if say is not None:
                say(f"symmetric: from the {met[0]}, {len(met[1].pieces)} pieces")
    sym = next((nb.branch for nb in family if nb.symmetric), None)
    if sym is not None and branching.switch:
        for k, (origin, branch) in enumerate(
            asymmetric_branches(
                params,
                sym,
                p_min=lo,
                p_max=hi,
                options=options,
                max_branches=branching.max_branches - len(family),
                known=known,
                say=say,
            )
        ):
            family.append(NamedImpactBranch("asymmetric" + (f"-{k + 1}" if k else ""), branch, False))
            if say is not None:
                say(f"{family[-1].name}: from the {origin}, {len(branch.pieces)} pieces")
    if branching.switch and branching.doublings:
        # the cascade, as for (9): each new branch of the full map a parent in turn, up to period 8
        count = {}
        k = 0
        while k < len(family) and len(family) < branching.max_branches:
            parent, k = family[k], k + 1
            multiple = parent.branch.pieces[0].period_multiple if parent.branch.pieces else 1
            if parent.symmetric or 2 * multiple > MAX_PERIOD_MULTIPLE:
                continue
            for origin, branch in doubled_branches(
                params,
                parent.branch,
                p_min=lo,
                p_max=hi,
                options=options,
                max_branches=branching.max_branches - len(family),
                say=say,
            ):
                count[2 * multiple] = count.get(2 * multiple, 0) + 1
                n = count[2 * multiple]
                family.append(
                    NamedImpactBranch(f"period-{2 * multiple}" + (f"-{n}" if n > 1 else ""), branch, False)
                )
                if say is not None:
                    say(
                        f"{family[-1].name}: from the {origin} on the {parent.name} branch, "
                        f"{len(branch.pieces)} pieces"
                    )
    return family


def impact_curve_starts(named: NamedImpactBranch, params: Params, box: dict, pitchforks=()):
    """The located LP, PD, NS (and, on a symmetric branch, BP) points of a branch of (8) (in
    sigma or Abar, at ``params``) and its grazing points as starts of curves over ``box``.
    ``pitchforks``: sigma at the family's pitchforks, where an asymmetric branch's LP (the mirror
    pair turning in sigma where it is born) is no fold."""
    param = named.branch.param
    if not named.symmetric:  # its own pitchforks too: a branch in Abar meets its parent there
        pitchforks = [*pitchforks, *(p for p, _ in named.branch.special("BP"))]
    yield from _grazing_starts(named, params, box)
    for piece in named.branch.pieces:
        for sp in piece.branch.special:
            if (
                sp.kind not in ("LP", "PD", "NS", "BP")
                or not sp.located
                or (sp.kind == "BP" and not named.symmetric)
            ):
                continue
            if (
                sp.kind == "LP"
                and not named.symmetric
                and any(abs(sp.p - q) <= 1e-6 * (1 + abs(q)) for q in pitchforks)
            ):
                continue
            if sp.kind == "LP" and _parents_orbit(params, param, piece, sp, named.branch.variant):
                continue  # a doubled branch turns where it is born: the parent's period doubling, no fold
            if _within_grazing_rule(params, param, named, piece, sp):
                continue  # a curve from there would end where it starts
            at = params.replace(**{param: float(sp.p)})
            origin = (
                f"{sp.kind} at sigma = {at.sigma:.6g}, Abar = {at.Abar:.6g} on the {named.name} branch "
                f"of {VARIANT_NAMES[named.branch.variant]} in {param}"
            )
            seed = ImpactCurveSeed(
                sp.kind,
                sp.x,
                float(sp.p),
                param,
                symmetric=named.symmetric,
                phase=piece.phase,
                impacts=piece.impacts,
                period_multiple=piece.period_multiple,
                origin=origin,
                variant=named.branch.variant,
            )
            yield CurveStart.with_job(
                sp.kind,
                at.sigma,
                at.Abar,
                origin,
                dict(trace=trace_impact_curve, params=params, seed=seed, box=box),
                side_at(piece.branch, sp),
            )


def _parents_orbit(params, param, piece, sp, variant) -> bool:
    """Whether the orbit at ``sp`` of a period-2 piece repeats after one forcing period to 1e-3
    (as :func:`~slosh_bif.orbits.codim2.repeats_early` for (9)): the parent's orbit, where the
    doubled branch is born at its period doubling (a fold located there is off the parent's orbit
    by the square root of its location's error)."""
    if piece.period_multiple == 1:
        return False
    single = ImpactOrbitProblem(
        params.replace(**{param: float(sp.p)}), param, phase=piece.phase, variant=variant
    )
    x = np.asarray(sp.x, dtype=float)
    return bool(np.linalg.norm(single.residual(x, sp.p)) <= 1e-3 * (1 + np.linalg.norm(x)))


def _within_grazing_rule(params, param, named, piece, sp) -> bool:
    """Whether the orbit at ``sp`` has an impact slower than
    :data:`~slosh_bif.orbits.impact.strobe.MIN_IMPACT_SPEED`: a point the curves count as their
    grazing edge (a fold within a few 1e-6 of a grazing, say). Impacts below the corrected impact
    model's least measured speed are the curves' own: they hold each impact's side of it."""
    problem = ImpactOrbitProblem(
        params.replace(**{param: float(sp.p)}),
        param,
        symmetric=named.symmetric,
        period_multiple=piece.period_multiple,
        phase=piece.phase,
        variant=named.branch.variant,
    )
    impacts = problem.evaluate(np.asarray(sp.x, dtype=float), sp.p).impacts
    return bool(len(impacts) and np.abs(impacts[:, 2]).min() < MIN_IMPACT_SPEED)


def _grazing_starts(named: NamedImpactBranch, params: Params, box: dict):
    """The grazing points of a branch of (8) (each once; a branch's two directions may end at the
    same one) as starts of grazing curves over ``box``."""
    param, seen = named.branch.param, []
    period_multiple = named.branch.pieces[0].period_multiple if named.branch.pieces else 1
    for p, x, phase in named.branch.grazing:
        if any(abs(p - q) <= 1e-8 * (1 + abs(q)) for q in seen):
            continue
        seen.append(p)
        at = params.replace(**{param: float(p)})
        origin = (
            f"GR at sigma = {at.sigma:.6g}, Abar = {at.Abar:.6g} on the {named.name} branch of "
            f"{VARIANT_NAMES[named.branch.variant]} in {param}"
        )
        seed = ImpactCurveSeed(
            "GR",
            x,
            float(p),
            param,
            symmetric=named.symmetric,
            phase=phase,
            period_multiple=period_multiple,
            origin=origin,
            variant=named.branch.variant,
        )
        job = dict(trace=trace_grazing_curve, params=params, seed=seed, box=box)
        yield CurveStart.with_job("GR", at.sigma, at.Abar, origin, job)


def _family_starts(family, params: Params, box: dict) -> list:
    """:func:`impact_curve_starts` of every branch of ``family`` (at ``params``), with the
    family's own pitchforks."""
    return [s for nb in family for s in impact_curve_starts(nb, params, box, _pitchforks(family))]


def _pitchforks(family) -> list:
    """The parameter values at the pitchforks of the family's symmetric branches (of (8))."""
    return [p for nb in family if nb.symmetric for p, _ in nb.branch.special("BP")]


def _seeds_in_abar(primary: NamedImpactBranch, piece, i: int, params: Params, abar_range, branching):
    """(the parameter set at its sigma, the branches): the orbit at point ``i`` of ``piece`` of the
    primary branch continued in Abar over ``abar_range`` at its sigma, switched as ``branching``
    says; no branches where it cannot be continued."""
    at = params.replace(sigma=float(piece.branch.p[i]))
    if not abar_range[0] <= params.Abar <= abar_range[1]:
        return at, []
    variant = primary.branch.variant
    problem = ImpactOrbitProblem(at, "sigma", symmetric=primary.symmetric, phase=piece.phase, variant=variant)
    try:
        x0 = state_at_zero(problem, piece.branch.x[i], at.sigma)
        return at, impact_family(
            at, x0, param="Abar", p_range=abar_range, branching=branching, variant=variant
        )
    except (ConvergenceError, ValueError):
        return at, []
