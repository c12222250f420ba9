"""The (sigma, Abar) chart of the full model (9): the curves where its periodic orbits fold (LP),
double their period (PD), lose stability to a torus (NS) or break their symmetry (BP), traced
from every such point of the orbit families (side by side on several processes), and the full
model's critical forcing read off them, beside the slow flow's Abar_b of (46).

The second parameter may be any other real field of :class:`Params` (``second="beta"``: the
(sigma, beta) chart); the critical forcing and the slow flow's Abar_b then have no meaning on the
chart and are left out.

What "critical" means on each model
-----------------------------------
* Slow flow (46): Abar_b(sigma) is the least forcing with a steady state on S+ at sigma, i.e.
  with a 1:1 resonant response of the reduced model (it may be unstable).
* Full model (9): Abar_c(sigma) is the least forcing at which the boundary of the region of
  *stable* period-1 orbits with wall contact (max |w| >= 1) lies at that sigma, read off the
  curves: a curve point bounds stable orbits when every multiplier but the critical one(s) is
  inside the unit circle. It is an envelope of curves, not a sweep.

  The LP, PD and NS curves all count (a BP curve bounds the symmetric orbits, not the stable
  ones: the asymmetric pair born there can be stable).

The two differ for three reasons: (46) is an asymptotic model (eps, 1/n); its steady states can
be unstable in (9) (the stable orbit is then elsewhere, or there is none: strongly modulated
response); and a stable orbit of (9) can lose stability through a period doubling or a torus
(NS) with (46) saying nothing about it.

:func:`critical_forcing_full` asks the same at one sigma (``answer critical-forcing`` and the
bench's ``critical_forcing.csv``): every family of orbits at that sigma, continued in Abar, and
the curves through their special points in a narrow sigma box; they cross that sigma at the
special points, so the envelope there is the lowest stable-bounding one.
"""

from __future__ import annotations

import dataclasses
import os
import time

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.continuation.branch import polyline_distance
from slosh_bif.model.params import Params
from slosh_bif.orbits.codim2 import BifurcationCurve, trace_curve
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.scan import scan_families
from slosh_bif.orbits.shooting import PARAMETERS, orbit_measures
from slosh_bif.orbits.starts import start_orbit
from slosh_bif.slowflow.critical import critical_curve, critical_forcing, interp_min

__all__ = ["Chart", "CurveFailure", "bifurcation_chart", "lowest_stable_boundary", "critical_rows", "CRITICAL_COLUMNS", "FullCritical", "critical_forcing_full", "check_box"]

CRITICAL_COLUMNS = ("sigma", "Abar_b_slowflow", "Abar_c_full", "rel_diff", "bounded_by")


@dataclasses.dataclass(frozen=True)
class CurveStart:
    """A special point of an orbit branch that a curve starts from."""

    kind: str
    sigma: float
    value: float  # of the chart's second parameter
    origin: str


@dataclasses.dataclass(frozen=True)
class CurveFailure(CurveStart):
    """A special point from which no curve could be started, and why."""

    reason: str


@dataclasses.dataclass(frozen=True)
class Chart:
    """The chart's pieces: the orbit family it started from, the curves, the slow flow's critical
    curve (None where (46) has none in the range), whether every start was tried (``status``) and
    the starts that gave no curve (``failures``, each with its reason)."""

    params: Params
    sigma_range: tuple
    abar_range: tuple  # the range of ``second``
    family: object
    curves: list
    slow_flow_critical: object
    seconds: float
    status: str = "complete"  # or why the curves stopped early ("interrupted (SIGINT) after ...")
    second: str = "Abar"  # the chart's second parameter
    failures: tuple = ()  # CurveFailure of each start that gave no curve

    @property
    def incomplete(self) -> list:
        """Why the chart is not the whole answer, one line each: curves cut short, starts that gave no curve."""
        cut = [f"curve {k} ({c.kind} from {c.origin}): {c.status}" for k, c in enumerate(self.curves) if c.status != "ok"]
        return cut + [f"no {f.kind} curve from {f.origin}: {f.reason}" for f in self.failures]


def _on_curve(curve: BifurcationCurve, sigma, value, tol=2e-3):
    return len(curve) > 0 and polyline_distance(np.column_stack([curve["sigma"], curve[curve.p2]]), np.array([sigma, value])) < tol


@dataclasses.dataclass(frozen=True)
class _Start(CurveStart):
    """A curve's start and its set-up (the arguments of :func:`trace_curve`)."""

    job: dict


def _starts(ob, param, params, sigma_range, abar_range, pitchforks=(), backend="auto", second="Abar"):
    """The located LP, PD, NS (and, on symmetric branches, BP) points of the orbit branch ``ob``
    (in ``param``, sigma or ``second``, at ``params``) as starts of curves in (sigma, ``second``);
    ``pitchforks``: the values of ``param`` at the family's pitchforks."""
    for sp in ob.branch.special:
        if sp.kind not in ("LP", "PD", "NS", "BP") or not sp.located:
            continue
        segments = ob.problem.segments * (2 if ob.problem.symmetric else 1)  # the curves start from the 2pi problem's states
        if sp.kind == "BP" and (ob.kind != "symmetric" or segments % 2):
            continue  # a pitchfork of symmetric orbits: the half-period map's condition
        if sp.kind == "LP" and ob.kind == "asymmetric" and any(abs(sp.p - q) <= 1e-6 * (1 + abs(q)) for q in pitchforks):
            continue  # where the pair meets its symmetric parent again: the pitchfork, not a fold
        sigma, value = (sp.p, getattr(params, second)) if param == "sigma" else (params.sigma, sp.p)
        origin = f"{sp.kind} at sigma = {sigma:.6g}, {second} = {value:.6g} on the {ob.name} branch in {param}"
        job = dict(
            params=params, x=ob.problem.full_states(sp.x), p=sp.p, kind=sp.kind, branch_param=param, p2=second, p1_range=sigma_range, p2_range=abar_range,
            segments=segments, period_multiple=ob.problem.period_multiple, origin=origin, backend=backend,
        )
        yield _Start(sp.kind, float(sigma), float(value), origin, job)


def _pitchforks(family) -> list:
    return [sp.p for ob in family.branches if ob.kind == "symmetric" for sp in ob.branch.special if sp.kind == "BP"]


def _trace_job(job):
    """One curve (in a worker): (curve, None), or (None, why not)."""
    try:
        return trace_curve(**job), None
    except (ConvergenceError, np.linalg.LinAlgError, ValueError) as err:
        return None, str(err)


def _trace_curves(starts, say, workers: int = 1, done=None, keep=None, keep_partial: bool = True):
    """(curves, status, failures): the curve through each start that lies on no curve of its kind
    traced from an earlier start, in start order, on ``workers`` processes; interrupted, the curves
    finished by then and a status saying so; a :class:`CurveFailure` for each start whose curve
    could not be started (in start order). ``keep_partial=False``: an interruption is raised on
    (for a caller whose answer would be wrong from part of the curves). ``done``: {start index: curve} from an earlier run
    (not traced again); ``keep(i, curve)`` is called as each curve finishes.

    Curves are independent, so they run side by side; a start is not submitted when a finished
    curve of its kind already passes through it, and a curve traced alongside one that covers it
    is dropped at the end, so the result is the sequential one, whatever the timing.
    """
    traced = {i: c for i, c in (done or {}).items() if i < len(starts) and c.origin == starts[i].origin}  # start index -> curve
    failed = {}  # start index -> why no curve

    def covered(i, among):
        return any(c.kind == starts[i].kind and _on_curve(c, starts[i].sigma, starts[i].value) for c in among)

    def record(i, result):
        curve, err = result
        if curve is None:
            failed[i] = CurveFailure(starts[i].kind, starts[i].sigma, starts[i].value, starts[i].origin, " ".join(err.split()))
            say(f"no {starts[i].kind} curve from {starts[i].origin}: {failed[i].reason}")
        else:
            traced[i] = curve
            if keep is not None:
                keep(i, curve)
            say(f"{curve.kind} curve from {starts[i].origin}: {len(curve)} points, {curve.status}")

    status = "complete"
    try:
        if workers <= 1 or len(starts) <= 1:
            for i in range(len(starts)):
                if not covered(i, traced.values()):
                    record(i, _trace_job(starts[i].job))
        else:
            _trace_in_pool(starts, workers, covered, record, traced)
    except KeyboardInterrupt as stop:  # keep what is traced; the caller marks the chart partial
        if not keep_partial:
            raise
        status = f"interrupted ({getattr(stop, 'signal_name', 'SIGINT')}) after {len(traced)} curves, {len(starts)} starts"
    kept = []
    for i in sorted(traced):
        if not covered(i, kept):
            kept.append(traced[i])
    # A failed start that a curve traced from another start passes through is covered, not missing.
    failures = tuple(failed[i] for i in sorted(failed) if not covered(i, kept))
    return kept, status, failures


def _trace_in_pool(starts, workers, covered, record, traced):
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    from slosh_bif.simulation.sweep import stop_pool, worker_setup

    pool = ProcessPoolExecutor(max_workers=workers, initializer=worker_setup)
    try:
        pending, running = list(range(len(starts))), {}
        while pending or running:
            while pending and len(running) < workers:
                i = pending.pop(0)
                if not covered(i, traced.values()):
                    running[pool.submit(_trace_job, starts[i].job)] = i
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                record(running.pop(future), future.result())
    except BaseException:
        stop_pool(pool)
        raise
    pool.shutdown()


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
    workers: int | None = None,
    backend: str = "auto",
    done=None,
    keep=None,
    progress=None,
    second: str = "Abar",
    model: str = "slowflow",
) -> Chart:
    """Trace the family of orbits at the parameter set's Abar over ``sigma_range`` (from a
    simulation from ``state0``) and the primary branch's orbits at ``seeds`` values of sigma
    continued in Abar, then the LP, PD, NS and BP curve through each of their special points
    (each curve once) in the box ``sigma_range`` x ``abar_range``, on ``workers`` processes (default:
    every core), integrating with ``backend``. Interrupted while tracing curves, it returns those
    finished, ``status`` saying so. ``done`` and ``keep``: see :func:`_trace_curves` (a resumed run
    with the same settings finds the same starts in the same order).

    ``second``: the chart's second parameter (any real field of :class:`Params` but sigma;
    ``abar_range`` is then its range, the seeds are continued in it, and there is no slow-flow
    critical curve). ``model``: the slow flow whose Abar_b is drawn beside the curves."""
    check_box(params, sigma_range, abar_range, second)
    (s0, s1), (a0, a1) = sigma_range, abar_range
    workers = _workers(workers)
    say = progress or (lambda message: None)
    started = time.perf_counter()
    start = start_orbit(params, state0, (s0, s1), settle=settle, segments=segments, backend=backend)
    family = trace_orbits(
        start.params, start.y0, p_min=s0, p_max=s1, segments=segments, switch=switch, max_branches=max_branches, backend=backend, progress=say,
    )
    say(f"orbit family: {len(family.branches)} branch(es), {sum(len(ob) for ob in family.branches)} points")
    pitchforks = _pitchforks(family)
    starts = [s for ob in family.branches for s in _starts(ob, "sigma", params, (s0, s1), (a0, a1), pitchforks, backend, second)]
    # Folds and period doublings met when the forcing falls: the primary branch's orbits at
    # ``seeds`` values of sigma, each continued in Abar (the second parameter) over the box.
    primary = family.branches[0]
    # Seed orbits are regular points: an orbit at a pitchfork continued in Abar shows its mirror
    # pair's meeting as spurious folds.
    regular = np.ones(len(primary.branch), dtype=bool)
    for sp in primary.branch.special:
        regular[max(sp.index - 2, 0) : sp.index + 3] = False
    for sigma in np.linspace(s0, s1, seeds + 2)[1:-1]:
        i = int(np.argmin(np.where(regular, np.abs(primary.branch.p - sigma), np.inf)))
        at = params.replace(sigma=float(primary.branch.p[i]))
        if not a0 <= getattr(at, second) <= a1:
            continue
        try:
            down = trace_orbits(at, primary.branch.x[i, :4], param=second, p_min=a0, p_max=a1, segments=segments, switch=False, backend=backend, progress=say)
        except (ConvergenceError, ValueError) as err:
            say(f"no {second} branch at sigma = {at.sigma:.4g}: {err}")
            continue
        starts += _starts(down.branches[0], second, at, (s0, s1), (a0, a1), backend=backend, second=second)
    say(f"{len(starts)} special points to start curves from, on {workers} process(es)")
    if done:
        say(f"{len(done)} curves from an earlier run")
    curves, status, failures = _trace_curves(starts, say, workers, done, keep)
    slow = None
    if second == "Abar":
        try:
            slow = critical_curve(params, s0, s1, model=model)
        except (RuntimeError, ValueError) as err:
            say(f"no slow-flow critical curve: {err}")
    return Chart(params, (s0, s1), (a0, a1), family, curves, slow, time.perf_counter() - started, status, second, failures)


def check_box(params: Params, sigma_range, second_range, second: str = "Abar"):
    """One line before any work unless ``second`` is a real field other than sigma, the box is
    not empty, both ends of the second range are admissible values (Abar >= 0, eps > 0, a real
    restitution coefficient, ...) and the parameter set lies inside the box."""
    if second == "sigma" or second not in PARAMETERS:
        raise ValueError(f"the chart's second parameter must be one of {', '.join(p for p in PARAMETERS if p != 'sigma')} (sigma is the first); got {second!r}")
    (s0, s1), (a0, a1) = sigma_range, second_range
    if not (s0 < s1 and a0 < a1):
        raise ValueError(f"empty box: sigma in [{s0}, {s1}], {second} in [{a0}, {a1}] (need sigma_min < sigma_max and {second}_min < {second}_max)")
    for end in (a0, a1):
        try:
            params.replace(**{second: end})
        except ValueError as err:
            raise ValueError(f"the box's {second} range [{a0:g}, {a1:g}] leaves the parameter's range: {err}") from None
    if not (s0 <= params.sigma <= s1 and a0 <= getattr(params, second) <= a1):
        raise ValueError(f"the start (sigma = {params.sigma:g}, {second} = {getattr(params, second):g}) lies outside the box")


@dataclasses.dataclass(frozen=True)
class FullCritical:
    """Abar_c of (9) at one sigma: NaN (and ``bounded_by`` empty) when no traced curve bounds
    stable orbits with wall contact there inside the Abar range; ``chart`` is what it was read off."""

    sigma: float
    Abar_c: float
    bounded_by: str
    chart: Chart


def critical_forcing_full(
    params: Params, state0, *, abar_range: tuple | None = None, halfwidth: float = 0.25, switch: bool = True, segments: int = 4, points: int = 5,
    settle: int = 100, random_starts: int = 4, seed: int = 0, progress=None, model: str = "slowflow",
) -> FullCritical:
    """Abar_c(sigma) of (9) at ``params.sigma``: every family of orbits there in Abar over
    ``abar_range`` (default [0.05, max(2 Abar, 3)]), found by :func:`~slosh_bif.orbits.scan.scan_families`
    (starts from ``state0`` and others at ``points`` values of Abar; switched at branch points,
    not at period doublings: only period-1 orbits count), then the curve through each
    of their LP, PD and NS points in the box sigma +- ``halfwidth`` x ``abar_range``; the lowest
    curve point at sigma that bounds stable period-1 orbits with wall contact.

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
        params, state0, p_min=a0, p_max=a1, param="Abar", points=points, settle=settle, random_starts=random_starts, seed=seed, segments=segments,
        switch=switch, doublings=False, progress=progress,
    )
    pitchforks = _pitchforks(family)
    starts = [s for ob in family.branches if ob.problem.period_multiple == 1 for s in _starts(ob, "Abar", params, box, (a0, a1), pitchforks)]
    curves, _, failures = _trace_curves(starts, say, keep_partial=False)
    try:
        slow = critical_curve(params, *box, model=model)
    except (RuntimeError, ValueError):
        slow = None
    chart = Chart(params, box, (a0, a1), family, curves, slow, time.perf_counter() - started, failures=failures)
    # The special points lie at sigma exactly; a curve read at sigma is interpolated between its
    # points (2e-3 off at the Fig. 13 set's NS), so it counts only where it crosses sigma away
    # from every special point: a crossing of a family the scan did not reach.
    exact = [(sp.p, sp.kind) for ob in family.branches if ob.problem.period_multiple == 1 for sp in ob.branch.special if _bounds_stable_contact(ob, sp)]
    value, kind = min(exact, default=(np.nan, ""))
    for c in curves:
        crossed = lowest_stable_boundary([c], sigma)[0]
        if np.isfinite(crossed) and not crossed >= value and not any(k == c.kind and abs(a - crossed) <= 0.01 * a for a, k in exact):
            value, kind = crossed, c.kind
    return FullCritical(float(sigma), float(value), kind, chart)


def _workers(workers):
    if workers is None:
        return os.cpu_count() or 1
    if not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers must be an integer >= 1; got {workers!r}")
    return workers


_CRITICAL_COUNT = {"LP": 1, "BP": 1, "PD": 1, "NS": 2}


def _bounds_stable_contact(ob, sp) -> bool:
    """Whether the located LP, PD or NS point ``sp`` of ``ob`` bounds stable orbits with wall
    contact: every multiplier but the critical one(s) inside the unit circle, max |w| >= 1."""
    if sp.kind not in ("LP", "PD", "NS") or not sp.located:
        return False
    mu = ob.problem.eigenvalues(sp.x, sp.p)
    target = {"LP": 1.0, "PD": -1.0}.get(sp.kind)
    distance = np.abs(mu - target) if target is not None else np.where(np.abs(mu.imag) > 1e-9, np.abs(np.abs(mu) - 1), np.inf)
    rest = np.delete(mu, np.argsort(distance)[: _CRITICAL_COUNT[sp.kind]])
    return bool(np.all(np.abs(rest) < 1) and orbit_measures(ob.problem, sp.x, sp.p)["max_abs_w"] >= 1.0)


def lowest_stable_boundary(curves, sigma):
    """(Abar, kind) of the lowest point at sigma of the ``curves`` that bounds stable period-1
    orbits with wall contact, by linear interpolation along each curve; (nan, "") when none."""
    best = (np.nan, "")
    for c in curves:
        if c.period_multiple != 1:
            continue  # a period-2 branch's curves bound period-2 orbits
        good = c.branch.stable & (c["max_abs_w"] >= 1.0)
        value = interp_min(c["sigma"], np.where(good, c["Abar"], np.nan), sigma)
        if value is not None and not value >= best[0]:
            best = (value, c.kind)
    return best


def _slow_flow_critical_at(params: Params, sigma: float, model: str) -> float:
    """Abar_b of the slow flow at sigma, computed there (not interpolated along the traced curve,
    whose chords between points lie up to 2e-3 above it); NaN where (46) has no steady state."""
    try:
        return critical_forcing(params, float(sigma), model=model).Abar_b
    except (RuntimeError, ValueError):
        return np.nan


def critical_rows(chart: Chart, points: int = 57):
    """``critical.csv`` rows: on a sigma grid, Abar_b of (46), Abar_c of (9) and which curve kind sets it
    (none for a chart whose second parameter is not Abar)."""
    if chart.second != "Abar":
        return
    slow = chart.slow_flow_critical
    for sigma in np.linspace(*chart.sigma_range, points):
        b = _slow_flow_critical_at(chart.params, sigma, slow.model) if slow is not None else np.nan
        c, kind = lowest_stable_boundary(chart.curves, sigma)
        rel = abs(c - b) / b if np.isfinite(b) and np.isfinite(c) and b > 0 else np.nan
        yield dict(sigma=float(sigma), Abar_b_slowflow=b, Abar_c_full=c, rel_diff=rel, bounded_by=kind)
