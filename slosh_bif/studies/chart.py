"""The (sigma, Abar) chart of the full model (9): the curves where its periodic orbits fold (LP)
or double their period (PD), traced from every such point of the orbit families, and the full
model's critical forcing read off them, beside the slow flow's Abar_b of (46).

What "critical" means on each model
-----------------------------------
* Slow flow (46): Abar_b(sigma) is the least forcing with a steady state on S+ at sigma, i.e.
  with a 1:1 resonant response of the reduced model (it may be unstable).
* Full model (9): Abar_c(sigma) is the least forcing at which the boundary of the region of
  *stable* period-1 orbits with wall contact (max |w| >= 1) lies at that sigma, read off the LP
  and PD curves: a curve point bounds stable orbits when every multiplier but the critical one
  is inside the unit circle. It is an envelope of curves, not a sweep.

The two differ for three reasons: (46) is an asymptotic model (eps, 1/n); its steady states can
be unstable in (9) (the stable orbit is then elsewhere, or there is none: strongly modulated
response); and a stable orbit of (9) can lose stability through a period doubling (or a torus,
not traced yet) with (46) saying nothing about it.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.continuation.branch import polyline_distance
from slosh_bif.model.params import Params
from slosh_bif.orbits.codim2 import BifurcationCurve, trace_curve
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.starts import orbit_from_simulation
from slosh_bif.slowflow.critical import critical_curve, interp_min

__all__ = ["Chart", "bifurcation_chart", "critical_rows", "CRITICAL_COLUMNS"]

CRITICAL_COLUMNS = ("sigma", "Abar_b_slowflow", "Abar_c_full", "rel_diff", "bounded_by")


@dataclasses.dataclass(frozen=True)
class Chart:
    """The chart's pieces: the orbit family it started from, the curves, and the slow flow's
    critical curve (None where (46) has none in the range)."""

    params: Params
    sigma_range: tuple
    abar_range: tuple
    family: object
    curves: list
    slow_flow_critical: object
    seconds: float


def _on_curve(curve: BifurcationCurve, sigma, abar, tol=2e-3):
    return len(curve) > 0 and polyline_distance(np.column_stack([curve["sigma"], curve["Abar"]]), np.array([sigma, abar])) < tol


def _curves_from(ob, param, params, curves, sigma_range, abar_range, say):
    """Trace the curve through each located LP, PD, NS (and, on symmetric branches, BP) of the
    orbit branch ``ob`` (in ``param`` at ``params``) that lies on no curve of its kind traced so
    far; append them to ``curves``."""
    for sp in ob.branch.special:
        if sp.kind not in ("LP", "PD", "NS", "BP") or not sp.located:
            continue
        if sp.kind == "BP" and (ob.name != "symmetric" or ob.problem.segments % 2):
            continue  # a pitchfork of symmetric orbits: the half-period map's condition
        sigma, abar = (sp.p, params.Abar) if param == "sigma" else (params.sigma, sp.p)
        if any(c.kind == sp.kind and _on_curve(c, sigma, abar) for c in curves):
            continue
        origin = f"{sp.kind} at sigma = {sigma:.6g}, Abar = {abar:.6g} on the {ob.name} branch in {param}"
        try:
            curve = trace_curve(
                params, sp.x, sp.p, kind=sp.kind, branch_param=param, p1_range=sigma_range, p2_range=abar_range,
                segments=ob.problem.segments, period_multiple=ob.problem.period_multiple, origin=origin,
            )
        except (ConvergenceError, np.linalg.LinAlgError, ValueError) as err:
            say(f"no {sp.kind} curve from {origin}: {err}")
            continue
        curves.append(curve)
        say(f"{sp.kind} curve {len(curves)} from {origin}: {len(curve)} points, {curve.status}")


def bifurcation_chart(
    params: Params,
    state0,
    *,
    sigma_range: tuple,
    abar_range: tuple,
    switch: bool = True,
    max_branches: int = 6,
    segments: int = 4,
    settle: int = 150,
    seeds: int = 7,
    progress=None,
) -> Chart:
    """Trace the family of orbits at the parameter set's Abar over ``sigma_range`` (from a
    simulation from ``state0``) and the primary branch's orbits at ``seeds`` values of sigma
    continued in Abar, then the LP, PD, NS and BP curve through each of their special points
    (each curve once) in the box ``sigma_range`` x ``abar_range``."""
    (s0, s1), (a0, a1) = sigma_range, abar_range
    if not (s0 < s1 and 0 <= a0 < a1):
        raise ValueError(f"empty box: sigma in [{s0}, {s1}], Abar in [{a0}, {a1}] (need sigma_min < sigma_max and 0 <= Abar_min < Abar_max)")
    if not (s0 <= params.sigma <= s1 and a0 <= params.Abar <= a1):
        raise ValueError(f"the start (sigma = {params.sigma:g}, Abar = {params.Abar:g}) lies outside the box")
    say = progress or (lambda message: None)
    started = time.perf_counter()
    start = orbit_from_simulation(params, state0, settle=settle, segments=segments)
    family = trace_orbits(start.params, start.y0, p_min=s0, p_max=s1, segments=segments, switch=switch, max_branches=max_branches)
    say(f"orbit family: {len(family.branches)} branch(es), {sum(len(ob) for ob in family.branches)} points")
    curves = []
    for ob in family.branches:
        _curves_from(ob, "sigma", params, curves, (s0, s1), (a0, a1), say)
    # Folds and period doublings met when the forcing falls: the primary branch's orbits at
    # ``seeds`` values of sigma, each continued in Abar over the box.
    primary = family.branches[0]
    for sigma in np.linspace(s0, s1, seeds + 2)[1:-1]:
        i = int(np.argmin(np.abs(primary.branch.p - sigma)))
        at = params.replace(sigma=float(primary.branch.p[i]))
        if not a0 <= at.Abar <= a1:
            continue
        try:
            down = trace_orbits(at, primary.branch.x[i, :4], param="Abar", p_min=a0, p_max=a1, segments=segments, switch=False)
        except (ConvergenceError, ValueError) as err:
            say(f"no Abar branch at sigma = {at.sigma:.4g}: {err}")
            continue
        _curves_from(down.branches[0], "Abar", at, curves, (s0, s1), (a0, a1), say)
    try:
        slow = critical_curve(params, s0, s1)
    except (RuntimeError, ValueError) as err:
        say(f"no slow-flow critical curve: {err}")
        slow = None
    return Chart(params, (s0, s1), (a0, a1), family, curves, slow, time.perf_counter() - started)


def _lowest_stable_boundary(chart: Chart, sigma):
    """(Abar, kind) of the lowest curve point at sigma that bounds stable period-1 orbits with
    wall contact, by linear interpolation along each curve; (nan, "") when none."""
    best = (np.nan, "")
    for c in chart.curves:
        good = c.branch.stable & (c["max_abs_w"] >= 1.0)
        value = interp_min(c["sigma"], np.where(good, c["Abar"], np.nan), sigma)
        if value is not None and not value >= best[0]:
            best = (value, c.kind)
    return best


def critical_rows(chart: Chart, points: int = 57):
    """``critical.csv`` rows: on a sigma grid, Abar_b of (46), Abar_c of (9) and which curve kind sets it."""
    slow = chart.slow_flow_critical
    for sigma in np.linspace(*chart.sigma_range, points):
        b = float(np.interp(sigma, slow.sigma, slow.Abar_b)) if slow is not None and len(slow.sigma) and slow.sigma[0] <= sigma <= slow.sigma[-1] else np.nan
        c, kind = _lowest_stable_boundary(chart, sigma)
        rel = abs(c - b) / b if np.isfinite(b) and np.isfinite(c) and b > 0 else np.nan
        yield dict(sigma=float(sigma), Abar_b_slowflow=b, Abar_c_full=c, rel_diff=rel, bounded_by=kind)
