"""The full model's critical forcing Abar_c(sigma), the least forcing with a stable orbit in wall
contact, at one sigma over every family there (:func:`critical_forcing_full`) and along a chart
(:func:`critical_rows`, read by :mod:`~slosh_bif.studies.chart.reading`), beside the slow flow's
Abar_b of (46) (the paper's Fig. 10-13 comparison)."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from slosh_bif.model.params import Params
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.scan import scan_families
from slosh_bif.orbits.settings import (
    BRANCHING,
    SHOOTING,
    STARTS,
    BranchingSettings,
    ParameterRange,
    ShootingSettings,
    StartSettings,
)
from slosh_bif.orbits.stable_contact import family_low_ends
from slosh_bif.slowflow.critical import critical_curve
from slosh_bif.studies.chart.curves import (
    curve_starts,
    pitchforks_of,
    trace_curves,
)
from slosh_bif.studies.chart.reading import (
    beyond_exit,
    critical_at,
    exits_below,
    low_end_reading,
    lowest_stable_boundary,
    variant_of,
)
from slosh_bif.studies.chart.result import Chart

__all__ = ["CRITICAL_COLUMNS", "FullCritical", "critical_forcing_full", "critical_rows"]


CRITICAL_COLUMNS = ("sigma", "Abar_b_slowflow", "Abar_c_full", "rel_diff", "bounded_by", "loss", "below_box")


@dataclasses.dataclass(frozen=True)
class FullCritical:
    """Abar_c of (9) at one sigma: the least Abar in the range with a stable orbit in wall
    contact, NaN (and ``bounded_by`` empty) where there is none, or where they reach the range's
    bottom (``below_range``: Abar_c lies below it); ``bounded_by`` the special point's kind, or
    "contact" where the stable orbit stops touching the walls smoothly; ``loss`` how the stable
    response is lost there (``jump`` at a fold, ``soft`` or ``hard`` by the normal-form
    coefficient of a PD, NS or BP point, ``undetermined`` near a codimension-2 point, ``none`` at a
    contact crossing); ``chart`` is what it was read off."""

    sigma: float
    Abar_c: float
    bounded_by: str
    chart: Chart
    loss: str = ""
    below_range: bool = False


def critical_forcing_full(
    params: Params,
    state0,
    *,
    abar_range: tuple | None = None,
    halfwidth: float = 0.25,
    starts: StartSettings = STARTS,
    shooting: ShootingSettings = SHOOTING,
    branching: BranchingSettings = BRANCHING,
    progress=None,
    model: str = "slowflow",
) -> FullCritical:
    """Abar_c(sigma) of (9) at ``params.sigma``: every family of orbits there in Abar over
    ``abar_range`` (default [0.05, max(2 Abar, 3)]), found by :func:`~slosh_bif.orbits.scan.scan_families`
    (starts from ``state0`` and others as ``starts`` says; switched at branch points as
    ``branching`` says, never at period doublings: only period-1 orbits count), then the curve through each
    of their LP, PD and NS points in the box sigma +- ``halfwidth`` x ``abar_range``. Abar_c is
    the lower end of the stable period-1 orbits with wall contact on those branches
    (:func:`~slosh_bif.orbits.stable_contact.lowest_stable_contact`), or a curve's crossing of
    sigma below it (with its stable side checked, :func:`~slosh_bif.studies.chart.reading.critical_at`).

    A single family misses stable orbits that no path in Abar at this sigma connects to it
    (Fig. 10 set, sigma = -1.2: the resonant orbit folds at Abar = 2.515, while a separate family
    has stable orbits with contact down to 0.34).
    """
    if not (np.isfinite(halfwidth) and halfwidth > 0):
        raise ValueError(f"halfwidth (of the sigma box) must be > 0; got {halfwidth!r}")
    a0, a1 = abar_range or (0.05, max(2.0 * params.Abar, 3.0))
    if not (0 <= a0 < a1):
        raise ValueError(f"abar_range must satisfy 0 <= Abar_min < Abar_max; got [{a0}, {a1}]")
    say = progress or (lambda message: None)
    started = time.perf_counter()
    sigma = params.sigma
    box = (sigma - halfwidth, sigma + halfwidth)
    family = scan_families(
        params,
        state0,
        starts=starts,
        shooting=shooting,
        branching=dataclasses.replace(branching, doublings=False),
        progress=progress,
        interval=ParameterRange(lo=a0, hi=a1, name="Abar"),
    )
    pitchforks = pitchforks_of(family)
    curve_box = {"sigma": box, "Abar": (a0, a1)}
    seeds = [
        s
        for ob in family.branches
        if ob.problem.period_multiple == 1
        for s in curve_starts(ob, params, curve_box, pitchforks, shooting)
    ]
    curves, _, failures = trace_curves(seeds, say, keep_partial=False)
    try:
        slow = critical_curve(params, *box, model=model)
    except (RuntimeError, ValueError):
        slow = None
    chart = Chart(
        params, box, (a0, a1), family, curves, slow, time.perf_counter() - started, failures=failures
    )
    # The lower ends of the stable orbits with contact on the branches in Abar, exact at sigma.
    ends = family_low_ends(family.branches, a0)
    if any(e.below_range for e in ends):
        return FullCritical(float(sigma), np.nan, "", chart, "", below_range=True)
    value, kind, loss, _ = min(
        (low_end_reading(e) for e in ends), key=lambda r: r[0], default=(np.nan, "", "", 0)
    )
    # A curve read at sigma is interpolated between its points (2e-3 off at the Fig. 13 set's NS),
    # so it counts only where it crosses sigma away from every special point: a crossing of a
    # family the scan did not reach.
    exact = [
        (sp.p, sp.kind)
        for ob in family.branches
        if ob.problem.period_multiple == 1
        for sp in ob.branch.special
        if _bounds_stable_contact(ob, sp)
    ]
    for c in curves:
        crossed = lowest_stable_boundary([c], sigma)[0]
        if (
            np.isfinite(crossed)
            and not crossed >= value
            and not any(kd == c.kind and abs(a - crossed) <= 0.01 * a for a, kd in exact)
        ):
            reading = critical_at([c], sigma, params, a0, shooting)
            if reading[3]:
                return FullCritical(float(sigma), np.nan, "", chart, "", below_range=True)
            if not reading[0] >= value:
                value, kind, loss = reading[:3]
    return FullCritical(float(sigma), float(value), kind, chart, loss)


_CRITICAL_COUNT = {"LP": 1, "BP": 1, "PD": 1, "NS": 2}


def _bounds_stable_contact(ob, sp) -> bool:
    """Whether the located LP, PD or NS point ``sp`` of ``ob`` bounds stable orbits with wall
    contact: every multiplier but the critical one(s) inside the unit circle, max |w| >= 1."""
    if sp.kind not in ("LP", "PD", "NS") or not sp.located:
        return False
    mu = ob.branch.eigenvalues[sp.index]
    target = {"LP": 1.0, "PD": -1.0}.get(sp.kind)
    distance = (
        np.abs(mu - target)
        if target is not None
        else np.where(np.abs(mu.imag) > 1e-9, np.abs(np.abs(mu) - 1), np.inf)
    )
    rest = np.delete(mu, np.argsort(distance)[: _CRITICAL_COUNT[sp.kind]])
    return bool(np.all(np.abs(rest) < 1) and orbit_measures(ob.problem, sp.x, sp.p)["max_abs_w"] >= 1.0)


def _slow_flow_critical_at(slow, sigma: float) -> float:
    """Abar_b of the slow flow at sigma, computed there rather than read off the chords of the
    traced curve ``slow`` (which lie up to 2e-3 above it): on an end of S+ by the end condition,
    at a fold by Brent's method on Abar(A) of (46) about the traced curve's amplitude (what
    :func:`~slosh_bif.slowflow.critical.critical_forcing` does over the whole window, at a
    fraction of its cost on walls whose kappa(A) is solved for); NaN outside the curve."""
    from scipy import optimize

    from slosh_bif.slowflow.critical import EndProblem
    from slosh_bif.slowflow.flow import SlowFlow
    from slosh_bif.slowflow.steady_states import abar_on_curve

    if slow is None or not len(slow.sigma) or not slow.sigma[0] <= sigma <= slow.sigma[-1]:
        return np.nan
    near = np.argsort(np.abs(slow.sigma - sigma))[:3]
    flow = SlowFlow(slow.params, slow.model)
    values = []
    for kind in set(slow.kind[near]):
        A = slow.A[near][slow.kind[near] == kind]
        try:
            if kind == "END":
                upper = slow.upper_end_branch is not None and abs(A[0] - flow.A_max) < abs(A[0] - flow.A_min)
                values.append(
                    EndProblem(slow.params, slow.model, "upper" if upper else "lower").abar_at(float(sigma))
                )
            else:
                lo, hi = max(flow.A_min, 0.9 * A.min()), min(flow.A_max, 1.1 * A.max())
                found = optimize.minimize_scalar(
                    lambda a: float(abar_on_curve(flow, a, sigma=float(sigma))),
                    bounds=(lo, hi),
                    method="bounded",
                    options={"xatol": 1e-13 * A.max()},
                )
                values.append(float(found.fun))
        except (RuntimeError, ValueError):
            continue
    return min(values, default=np.nan)


def critical_rows(chart: Chart, points: int = 57):
    """``critical.csv`` rows: on a sigma grid, Abar_b of (46), Abar_c of (9) (:func:`~.reading.critical_at`),
    which curve kind sets it ("contact" where the stable orbit below the curves stops touching the
    walls) and how the stable response is lost there (``loss``: jump, soft, hard, undetermined,
    none; '' where no coefficient was computed), and ``below_box`` 1 where stable orbits with
    contact reach the box's lowest Abar (below the lowest curve, or on a branch along the box's
    bottom, :func:`~.bottom.below_bottom`: no Abar_c there), or beyond a sigma where a curve
    bounding stable orbits leaves through it (:func:`~.reading.exits_below`): the least stable
    forcing may lie below the box there; none for a chart whose second parameter is not Abar, nor
    for a chart stopped part way (:attr:`~.result.Chart.reads_critical`)."""
    if not chart.reads_critical:
        return
    exits = exits_below(chart)
    slow = chart.slow_flow_critical
    sides = {}
    variant = variant_of(chart) or "paper"
    for sigma in np.linspace(*chart.sigma_range, points):
        b = _slow_flow_critical_at(slow, sigma)
        c, kind, loss, below = critical_at(
            chart.curves,
            sigma,
            chart.params,
            chart.abar_range[0],
            sides=sides,
            variant=variant,
            bottom=chart.bottom,
        )
        rel = abs(c - b) / b if np.isfinite(b) and np.isfinite(c) and b > 0 else np.nan
        below = below or beyond_exit(exits, sigma)
        yield dict(
            sigma=float(sigma),
            Abar_b_slowflow=b,
            Abar_c_full=c,
            rel_diff=rel,
            bounded_by=kind,
            loss=loss,
            below_box=int(below),
        )
