"""The curves of the (sigma, Abar) chart traced from the special points of orbit branches: which
points start a curve, each curve traced once (side by side on several processes, the result the
sequential one), and the starts that give no curve, with their reasons. The curves are the
minimally augmented fold, period-doubling, Neimark-Sacker and symmetry-breaking conditions of
periodic orbits of (9) (:mod:`slosh_bif.orbits.codim2`)."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.continuation.branch import polyline_distance
from slosh_bif.orbits.codim2 import (
    BifurcationCurve,
    CurveSeed,
    repeats_early,
    trace_curve,
)
from slosh_bif.orbits.orbit_tools import is_symmetric, symmetrized
from slosh_bif.orbits.settings import SHOOTING, ShootingSettings
from slosh_bif.report.tasks import Task

__all__ = [
    "CurveStart",
    "CurveFailure",
    "curve_starts",
    "family_starts",
    "torus_starts",
    "pitchforks_of",
    "repeats_early",
    "trace_curves",
    "side_at",
]


@dataclasses.dataclass(frozen=True)
class CurveStart:
    """A special point of an orbit branch that a curve starts from."""

    kind: str
    sigma: float
    value: float  # of the chart's second parameter
    origin: str

    @staticmethod
    def with_job(
        kind: str, sigma: float, value: float, origin: str, job: dict, inside: bool | None = None
    ) -> "CurveStart":
        """The start and its set-up: the keyword arguments of :func:`trace_curve`, or of the
        tracer given as ``job["trace"]`` (the curves of (8)); ``inside``: whether the start's
        other multipliers lie inside the unit circle (:func:`side_at`; None: not known)."""
        return _Start(kind, sigma, value, origin, job, inside)


SIDE_MARGIN = 1e-2  # a curve point's largest other multiplier this near the unit circle tells no side


@dataclasses.dataclass(frozen=True)
class CurveFailure(CurveStart):
    """A special point from which no curve could be started, and why."""

    reason: str


def _on_curve(curve: BifurcationCurve, sigma, value, tol=2e-3):
    return (
        len(curve) > 0
        and polyline_distance(np.column_stack([curve["sigma"], curve[curve.p2]]), np.array([sigma, value]))
        < tol
    )


def _covers(curve: BifurcationCurve, start) -> bool:
    """Whether ``curve`` passes through ``start``: of its kind, within 2e-3 in (sigma, p2), and,
    for a fold whose side is known, with the other multipliers on the start's side of the unit
    circle at the curve's nearest point (two fold curves can lie that close, one bounding stable
    orbits and one not). Torus curves are not told apart so: the pair a point of one treats as
    critical can be a neutral saddle's."""
    if curve.kind != start.kind or not _on_curve(curve, start.sigma, start.value):
        return False
    inside = getattr(start, "inside", None)
    if inside is None or start.kind != "LP":
        return True
    j = int(np.argmin(np.hypot(curve["sigma"] - start.sigma, curve[curve.p2] - start.value)))
    largest = float(curve["max_abs_multiplier"][j])
    return not np.isfinite(largest) or abs(largest - 1.0) < SIDE_MARGIN or (largest < 1.0) == inside


@dataclasses.dataclass(frozen=True)
class _Start(CurveStart):
    """A curve's start and its set-up (the arguments of :func:`trace_curve`, or of ``job["trace"]``),
    and which side of the unit circle its other multipliers lie on (None: not known)."""

    job: dict
    inside: bool | None = None


def curve_starts(ob, params, box: dict, pitchforks=(), shooting: ShootingSettings = SHOOTING):
    """The located LP, PD, NS (and, on symmetric branches, BP) points of the orbit branch ``ob``
    (continued in sigma or the chart's second parameter, at ``params``) as starts of curves over
    ``box`` ({"sigma": range, second: range}), computed with ``shooting``; ``pitchforks``: the
    values of the branch's parameter at the family's pitchforks."""
    param, second = ob.branch.param, list(box)[1]
    for sp in ob.branch.special:
        if sp.kind not in ("LP", "PD", "NS", "BP") or not sp.located:
            continue
        segments = ob.problem.segments * (
            2 if ob.problem.symmetric else 1
        )  # the curves start from the 2pi problem's states
        if sp.kind == "BP" and (ob.kind != "symmetric" or segments % 2):
            continue  # a pitchfork of symmetric orbits: the half-period map's condition
        if (
            sp.kind == "LP"
            and ob.kind == "asymmetric"
            and any(abs(sp.p - q) <= 1e-6 * (1 + abs(q)) for q in pitchforks)
        ):
            continue  # where the pair meets its symmetric parent again: the pitchfork, not a fold
        if sp.kind == "LP" and repeats_early(ob.problem, sp.x):
            continue  # the parent's orbit at its period doubling, where the branch is born or ends: no fold
        sigma, value = (sp.p, getattr(params, second)) if param == "sigma" else (params.sigma, sp.p)
        where = f"at sigma = {sigma:.6g}, {second} = {value:.6g} on the {ob.name} branch in {param}"
        arcs = shooting.replace(
            segments=segments // ob.problem.period_multiple
        )  # the branch's own arcs per forcing period
        seed = CurveSeed.on(ob, sp, f"{sp.kind} {where}")
        if sp.kind == "LP" and is_symmetric(ob.problem, sp.x):
            # The pair meets its symmetric parent (a family traced without it, or in another
            # parameter): the parent's pitchfork, whose curve starts from the symmetric orbit.
            origin = f"BP (the turn of the pair where it meets its symmetric parent) {where}"
            seed = dataclasses.replace(seed, kind="BP", x=symmetrized(seed.x), origin=origin)
        job = dict(params=params, seed=seed, box=box, shooting=arcs)
        inside = side_at(ob.branch, sp) if seed.kind == sp.kind else None
        yield CurveStart.with_job(seed.kind, float(sigma), float(value), seed.origin, job, inside)


def side_at(branch, sp) -> bool | None:
    """For a fold ``sp`` of ``branch``: whether its multipliers but the critical one (the nearest
    to +1) lie inside the unit circle, read at the located point itself (a branch holds it among
    its points); None for another kind, where the point is not among the branch's, or where the
    largest other multiplier lies within :data:`SIDE_MARGIN` of the circle. The stability of the
    points beside the fold is no guide: another multiplier can cross the circle between them,
    unlocated."""
    eigenvalues = getattr(branch, "eigenvalues", None)
    if sp.kind != "LP" or eigenvalues is None:
        return None
    p = np.asarray(branch.p, dtype=float)
    at = [j for j in (sp.index, sp.index + 1, sp.index - 1) if 0 <= j < len(p) and p[j] == sp.p]
    if not at:
        return None
    mu = np.asarray(eigenvalues[at[0]])
    if not np.all(np.isfinite(mu)) or len(mu) < 2:
        return None
    largest = float(np.abs(np.delete(mu, np.argmin(np.abs(mu - 1.0)))).max())
    return None if abs(largest - 1.0) < SIDE_MARGIN else largest < 1.0


def family_starts(family, params, box: dict, shooting: ShootingSettings = SHOOTING) -> list:
    """:func:`curve_starts` of every branch of the orbit ``family`` (at ``params``), with the
    family's own pitchforks."""
    pitchforks = pitchforks_of(family)
    return [s for ob in family.branches for s in curve_starts(ob, params, box, pitchforks, shooting)]


def torus_starts(curves, params, box: dict, shooting: ShootingSettings = SHOOTING):
    """Starts of the Neimark-Sacker curves that the traced fold and period-doubling ``curves`` meet
    at their located LPNS and PDNS points and that no traced NS curve passes through: an NS curve
    is found from the orbit branches only where the branch's steps see its test change sign, and
    two NS points a few 1e-5 apart beside a fold (seen on the period-4 branch of the Fig. 10 set)
    fall inside one step; the curve they bound still meets the fold curve, where it starts here."""
    tori = [c for c in curves if c.kind == "NS"]
    second = list(box)[1]
    for curve in curves:
        if curve.kind not in ("LP", "PD") or curve.p1 != "sigma":
            continue
        for sp in curve.branch.special:
            sigma, value = float(sp.p), float(sp.x[-1])
            if sp.kind not in ("LPNS", "PDNS") or any(_on_curve(c, sigma, value) for c in tori):
                continue
            where = f"{sp.kind} at sigma = {sigma:.6g}, {second} = {value:.6g}"
            origin = f"{where} on the {curve.kind} curve from {curve.origin}"
            states = sp.x[:-1]
            seed = CurveSeed("NS", states, sigma, "sigma", curve.period_multiple, origin)
            arcs = shooting.replace(segments=len(states) // (4 * curve.period_multiple))
            job = dict(
                params=params.replace(sigma=sigma, **{second: value}), seed=seed, box=box, shooting=arcs
            )
            yield CurveStart.with_job("NS", sigma, value, origin, job)


def pitchforks_of(family) -> list:
    return [
        sp.p
        for ob in family.branches
        if ob.kind == "symmetric"
        for sp in ob.branch.special
        if sp.kind == "BP"
    ]


def _trace_job(job):
    """One curve (in a worker): (curve, None, seconds), or (None, why not, seconds); the seconds
    are reported only (tasks.csv), never used."""
    arguments = dict(job)
    trace = arguments.pop("trace", trace_curve)
    began = time.perf_counter()
    try:
        curve, err = trace(**arguments), None
    except (ConvergenceError, np.linalg.LinAlgError, ValueError) as error:
        curve, err = None, str(error)
    return curve, err, time.perf_counter() - began


def trace_curves(
    starts,
    say,
    workers: int = 1,
    done=None,
    keep=None,
    keep_partial: bool = True,
    executor=None,
    tasks: list | None = None,
):
    """(curves, status, failures): the curve through each start that lies on no curve of its kind
    traced from an earlier start, in start order, on ``workers`` processes; interrupted, the curves
    finished by then and a status saying so; a :class:`CurveFailure` for each start whose curve
    could not be started (in start order). ``keep_partial=False``: an interruption is raised on
    (for a caller whose answer would be wrong from part of the curves). ``done``: {start index: curve} from an
    earlier run
    (not traced again); ``keep(i, curve)`` is called as each curve finishes. ``executor``: a
    cluster's (:class:`~slosh_bif.simulation.sweep.ClusterExecutor`), ``workers`` curves at once
    on it, instead of local processes. ``tasks``: a list that gets one :class:`Task` per curve
    traced (its start, duration and size), in the order they finish.

    Curves are independent, so they run side by side; a start is not submitted when a curve of its
    kind that the sequential run keeps (from the starts before it, all finished) passes through
    it, and a curve traced alongside one that covers it is dropped at the end, so the result is
    the sequential one, whatever the timing.
    """
    traced = {
        i: c for i, c in (done or {}).items() if i < len(starts) and c.origin == starts[i].origin
    }  # start index -> curve
    failed = {}  # start index -> why no curve

    def covered(i, among):
        return any(_covers(c, starts[i]) for c in among)

    def record(i, result):
        curve, err, seconds = result
        if tasks is not None:
            tasks.append(
                Task(i, starts[i].kind, starts[i].origin, seconds, 0 if curve is None else len(curve))
            )
        if curve is None:
            failed[i] = CurveFailure(
                starts[i].kind, starts[i].sigma, starts[i].value, starts[i].origin, " ".join(err.split())
            )
            say(f"no {starts[i].kind} curve from {starts[i].origin}: {failed[i].reason}")
        else:
            traced[i] = curve
            if keep is not None:
                keep(i, curve)
            say(f"{curve.kind} curve from {starts[i].origin}: {len(curve)} points, {curve.status}")

    status = "complete"
    try:
        if executor is None and (workers <= 1 or len(starts) <= 1):
            for i in range(len(starts)):
                if not covered(i, traced.values()):
                    record(i, _trace_job(starts[i].job))
        else:
            _trace_in_pool(starts, workers, covered, record, traced, executor)
    except KeyboardInterrupt as stop:  # keep what is traced; the caller marks the chart partial
        if not keep_partial:
            raise
        status = (
            f"interrupted ({getattr(stop, 'signal_name', 'SIGINT')}) after {len(traced)} curves, "
            f"{len(starts)} starts"
        )
    kept = []
    for i in sorted(traced):
        if not covered(i, kept):
            kept.append(traced[i])
    # A failed start that a curve traced from another start passes through is covered, not missing.
    failures = tuple(failed[i] for i in sorted(failed) if not covered(i, kept))
    return kept, status, failures


class _OnCluster:
    """A cluster's executor as a pool: stopping it cancels what has not finished (the cluster's
    workers stay); closing it leaves the cluster as it is."""

    def __init__(self, executor):
        self.executor, self.futures = executor, []

    def submit(self, function, *arguments):
        self.futures.append(self.executor.submit(function, *arguments))
        return self.futures[-1]

    def stop(self) -> None:
        for future in self.futures:
            future.cancel()

    def close(self) -> None:
        pass


def _trace_in_pool(starts, workers, covered, record, traced, executor=None):
    from concurrent.futures import FIRST_COMPLETED, wait

    from slosh_bif.simulation.sweep import WorkerPool

    pool = WorkerPool(workers) if executor is None else _OnCluster(executor)
    resolved = set(traced)  # starts traced, failed or skipped

    def settled_curves(kind):
        """The curves of ``kind`` that the sequential run keeps from the starts of that kind before
        the first of that kind not yet traced: only these may skip a start of that kind. Only a curve
        of a start's own kind can cover it, so what the sequential run keeps of one kind does not
        wait for the other kinds' curves; a curve from a later start, or from one the sequential
        run would skip, may not skip one: the result must not depend on which finishes first."""
        kept = []
        for k in range(len(starts)):
            if starts[k].kind != kind:
                continue
            if k not in resolved:
                break
            if k in traced and not covered(k, kept):
                kept.append(traced[k])
        return kept

    try:
        pending, running = list(range(len(starts))), {}
        while pending or running:
            while pending and len(running) < workers:
                i = pending.pop(_next_start(pending, [starts[k].kind for k in running.values()], starts))
                if covered(i, settled_curves(starts[i].kind)):
                    resolved.add(i)
                else:
                    running[pool.submit(_trace_job, starts[i].job)] = i
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                i = running.pop(future)
                record(i, future.result())
                resolved.add(i)
    except BaseException:
        pool.stop()
        raise
    pool.close()


def _next_start(pending, running_kinds, starts) -> int:
    """Where in ``pending`` the next start to trace is: the first whose kind no running curve has
    (only a curve of its kind can cover a start, so its trace is not wasted on a duplicate of
    one still running: on the Fig. 13 chart 17 of 56 curve tasks were), else the first. The
    order of tracing changes nothing kept: that is decided in start order at the end."""
    return next((n for n, i in enumerate(pending) if starts[i].kind not in running_kinds), 0)
