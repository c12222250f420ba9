"""Pseudo-arclength continuation (Keller), knowing nothing about sloshing.

A problem is what :mod:`slosh_bif.continuation.problem` writes down as types: ``names``,
``residual``, ``jacobian``, ``dparam``, and optional capabilities (a domain and its edges,
stability, the problem's own test functions, an ``accept`` hook), read once per problem by
:func:`~slosh_bif.continuation.problem.capabilities`.

With ``u = (x, p)`` and the unit tangent ``t`` of the curve F(u) = 0, each step predicts the
next point at arclength h (:mod:`.predictor`: the cubic through the last two points and their
tangents, or the tangent plus its turn) and corrects by Newton on the bordered system
``[F(u); t . (u - u_pred)] = 0``,
whose matrix ``[[F_x, F_p], [t^T]]`` stays regular through folds. The step h grows after easy
corrections and shrinks after slow or failed ones (or when a point leaves the domain), between
``step_min`` and ``step_max``.

Special points are detected and located by :mod:`.detection`; the bordered corrector is in
:mod:`.corrector`, options and end reasons in :mod:`.options`.

:func:`switch_branch` starts a new branch at a located branch point, along the direction of the
two-dimensional null space of ``[F_x, F_p]`` that the old branch does not take, with a sign fixed
by the direction itself (:func:`canonical_sign`).

Each direction ends at a parameter bound (the end is computed on the bound), at the domain's
edge, on closing a loop, at a located special point of one of the problem's ``terminal_kinds``
(or one the caller's ``stop`` picks), after ``max_steps``, or when the step falls below
``step_min``.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from slosh_bif.continuation.branch import Branch, SpecialPoint
from slosh_bif.continuation.corrector import (
    Point,
    correct,
    in_domain,
    initial_tangent,
    make_point,
    newton,
    top_rows,
)
from slosh_bif.continuation.detection import special_between
from slosh_bif.continuation.ends import at_named_edge, end_after_failures, end_on_bound, mark_end, stalls
from slosh_bif.continuation.options import (
    COMPLETE,
    LOOP,
    STALL,
    STEPS,
    TERMINAL,
    TIME,
    ContinuationOptions,
    ConvergenceError,
)
from slosh_bif.continuation.predictor import predictor
from slosh_bif.continuation.problem import capabilities, require_problem
from slosh_bif.continuation.steps import UNEXPLAINED_FLOOR, next_step, passes_start, stability_changes, stamp

__all__ = ["continuation", "switch_branch"]

# A direction whose accepted steps stay at most CREEP * step_min for CREEP_STEPS points in a row
# ends as a stall: it is creeping along a singular point (seen on fold curves past a cusp, with
# 2,000 points in 1e-7 of parameter), not making progress.
CREEP, CREEP_STEPS = 1e3, 50

# A direction that stalls at a point where the problem is nearly singular may only lack
# precision there (a fold curve's second derivatives are finite differences of integrations
# to rtol): a problem that offers ``refined()`` is resumed from the stall with that finer
# version, at most this many times per direction, before the stall is reported.
REFINEMENTS = 2

# Components of a switching direction within this fraction of its largest in size count as tied
# for :func:`canonical_sign` (mirror images give exact ties; rounding moves them by 1e-13 or so).
TIE = 1e-6


def _run(problem, start: Point, opts, loop_guard: bool, callback=None, stop=None):
    """One direction from ``start``: predict, correct, adapt the step, detect and locate special
    points, until an end; returns (points, end reason). ``stop(kind, x, p, index)``: whether the
    located special point about to take place ``index`` of the run ends it (as a terminal kind
    does)."""
    points = [start]
    h = opts.step
    edge_hits = 0
    bend = None  # no turn known before the first step: a straight tangent predictor
    crept = 0  # accepted steps in a row at most CREEP * step_min
    refinements = 0  # times this direction was resumed with a finer problem after a stall
    caps = capabilities(problem)
    accept, terminal = caps.accept, caps.terminal_kinds
    stamped = 0  # points[:stamped] have their stability (computed while the problem's caches hold them)
    deadline = time.monotonic() + opts.max_seconds
    while True:
        for q in points[stamped:]:
            stamp(caps, q)
        stamped = len(points)
        if len(points) > opts.max_steps:
            mark_end(points[-1], STEPS, f"{STEPS} ({opts.max_steps} steps)")
            return points, STEPS
        if time.monotonic() > deadline:
            mark_end(
                points[-1],
                TIME,
                f"{TIME} ({opts.max_seconds:g} s of wall clock, a safety net: where it ends "
                "depends on the machine's load)",
            )
            return points, TIME
        a = points[-1]
        predict = predictor(points, bend, h, opts)
        u, iters = correct(problem, predict(h), a.t, opts)
        if u is None:  # failed: halve, and end when the step is below its minimum
            edge_hits += not in_domain(problem, predict(h)) or iters < opts.max_newton
            h *= 0.5
            if h < opts.step_min:
                finer = _finer(caps, refinements) if stalls(caps, points[-1], edge_hits) else None
                if finer is not None:  # resume with the finer problem from the last point
                    problem, caps, refinements, h, bend = (
                        finer,
                        capabilities(finer),
                        refinements + 1,
                        opts.step,
                        None,
                    )
                    accept, terminal = caps.accept, caps.terminal_kinds
                    _restart_at(finer, points)
                    continue
                return points, end_after_failures(problem, points, h, edge_hits, opts)
            continue
        edge_hits = 0
        if not opts.p_min <= u[-1] <= opts.p_max:
            return points, end_on_bound(problem, points, u, opts)
        b = make_point(problem, u, a.t, iters)
        angle = math.acos(min(1.0, max(-1.0, float(b.t @ a.t))))
        if angle > 2 * opts.max_angle and h > 2 * opts.step_min:
            h *= 0.5 * opts.max_angle / angle + 0.25  # turned far too sharply: redo shorter
            continue
        found = special_between(problem, a, b, h, opts, predict)
        if not found and h > UNEXPLAINED_FLOOR * opts.step_max and stability_changes(caps, a, b):
            h *= 0.5  # stability changed with no special point between: two events in one step
            continue
        end = next((i for i, q in enumerate(found) if _ends(q, terminal, stop, len(points) + i)), None)
        if end is not None:  # the curve ends at this point by nature: nothing beyond it is kept
            points.extend(found[: end + 1])
            points[-1].reason = TERMINAL
            return points, TERMINAL
        points.extend(found)
        points.append(b)
        if opts.curved_predictor:  # the tangent's turn per unit arclength over the last step
            bend = (b.t - a.t) / max(float(np.linalg.norm(b.u - a.u)), np.finfo(float).tiny)
        if accept is not None:
            accept(b.u[:-1], b.u[-1])
        if callback is not None:
            callback(float(u[-1]), u[:-1])
        crept = crept + 1 if h <= CREEP * opts.step_min else 0
        if crept >= CREEP_STEPS and (finer := _finer(caps, refinements)) is not None:
            # Newton converges only for tiny steps: resume where the creeping began with the finer problem
            del points[len(points) - crept :]
            problem, caps, refinements, h, bend, crept = (
                finer,
                capabilities(finer),
                refinements + 1,
                opts.step,
                None,
                0,
            )
            accept, terminal = caps.accept, caps.terminal_kinds
            _restart_at(finer, points)
            continue
        if crept >= CREEP_STEPS and at_named_edge(caps, points[-1]):
            # creeping up to the domain's edge (a slow impact's 1/v saltation near grazing): the edge
            return points, end_after_failures(problem, points, h, 1, opts)
        if crept >= CREEP_STEPS:  # Newton converges only for tiny steps: a singular point, not progress
            mark_end(
                points[-1],
                STALL,
                f"{STALL}: {CREEP_STEPS} steps in a row below {CREEP * opts.step_min:.1g} (a "
                "singular point of the system)",
            )
            return points, STALL
        if loop_guard and len(points) > 3 and passes_start(start, a.u, u, h):
            # A closed curve has no end: the branch's message says it closed, no point is an END.
            return points, LOOP
        h = next_step(h, iters, angle, opts)


def _ends(q: Point, terminal, stop, index) -> bool:
    """Whether the located special point q ends its direction: a terminal kind, or ``stop`` says so."""
    return q.located and (q.kind in terminal or (stop is not None and stop(q.kind, q.u[:-1], q.u[-1], index)))


def _finer(caps, refinements):
    """The problem's finer version to resume a stalled direction with (None: it has none, or this
    direction was resumed ``REFINEMENTS`` times already)."""
    if caps.refined is None or refinements >= REFINEMENTS:
        return None
    return caps.refined()


def _restart_at(problem, points):
    """The last point's tangent and tests recomputed with ``problem`` (the finer one), so that the
    next step's sign changes compare values of one problem; its stability stays as stamped."""
    a = points[-1]
    q = make_point(problem, a.u, a.t, a.iterations)
    a.t, a.tests, a.jac = q.t, q.tests, q.jac
    a.refined = True


# -- the driver ------------------------------------------------------------------------------------


def continuation(
    problem, x0, p0, *, param="p", options: ContinuationOptions | None = None, orient=None, callback=None
) -> Branch:
    """Trace the solution curve of ``problem`` through ``(x0, p0)``; returns a :class:`Branch`.

    ``x0`` is corrected at fixed ``p0`` first, or, where that is singular (a start at a fold),
    along the branch's tangent (a :class:`ConvergenceError` says why when neither works). Mid-branch failures
    do not raise: the branch ends there with the reason.
    ``orient`` (a vector in (x, p)) makes "forward" the direction along it instead of along
    increasing p (needed where the branch runs across the parameter, as after a pitchfork).
    ``callback(p, x)``, if given, is called after every accepted point (for progress reports).
    """
    opts = options or ContinuationOptions()
    require_problem(problem)  # a TypeError naming what is missing, before any work
    if not opts.p_min <= p0 <= opts.p_max:
        raise ValueError(
            f"start parameter {param} = {p0} lies outside [p_min, p_max] = [{opts.p_min}, {opts.p_max}]"
        )
    x0 = np.atleast_1d(np.asarray(x0, dtype=float))
    if len(x0) != len(problem.names) or not np.all(np.isfinite(x0)):
        raise ValueError(
            f"x0 must be {len(problem.names)} finite numbers ({', '.join(problem.names)}); got {x0}"
        )
    try:
        u0 = np.append(newton(problem, x0, p0, tol=opts.tol), p0)
    except ConvergenceError as err:
        # At (or very near) a fold F_x is singular and Newton at fixed p fails; the bordered
        # corrector along the tangent of [F_x, F_p] is regular there (p may move a little).
        guess = np.append(x0, p0)
        u0, _ = correct(problem, guess, initial_tangent(problem, guess, True), opts)
        if u0 is None:
            raise ConvergenceError(
                f"{err}; the pseudo-arclength corrector from the same point failed too"
            ) from None
    return _trace(problem, u0, param, opts, orient, callback)


def switch_branch(
    problem,
    point,
    *,
    param="p",
    options: ContinuationOptions | None = None,
    along=None,
    step=None,
    callback=None,
    stop=None,
) -> Branch:
    """The branch that crosses the old one at a located branch point, traced away from it.

    ``point`` is a :class:`SpecialPoint` (or an ``(x, p)`` pair) at a simple branch point of
    ``problem``: the null space of ``[F_x, F_p]`` there is two-dimensional. ``along`` is the old
    branch's tangent (or any vector in that null space to avoid); the new direction is the null
    vector orthogonal to it, signed by :func:`canonical_sign` (not by the SVD's rounding). The
    first point is ``u_BP + step * t_new`` corrected on the hyperplane through it normal to t_new;
    the branch is traced forward from there (away from the branch point; the part behind it is,
    for a symmetry-breaking pitchfork, the mirror image).
    ``stop(kind, x, p, index)``, if given, ends the branch at the first located special point
    (at place ``index`` of the branch) for which it is true, as at a terminal kind: where the new
    branch meets its parent again, say, beyond which it is the image of what it traced.
    Raises :class:`ConvergenceError` when no new branch is found.
    """
    if along is None:
        raise ValueError("switch_branch needs along= (the old branch's tangent at the branch point)")
    opts = options or ContinuationOptions()
    require_problem(problem)
    x, p = (point.x, point.p) if hasattr(point, "x") else point
    u = np.append(np.asarray(x, dtype=float), float(p))
    null = np.linalg.svd(top_rows(problem, u)[1])[2][-2:]  # the two smallest right singular vectors
    coef = null @ np.asarray(along, dtype=float)  # the old direction, in the null space's basis
    t_new = canonical_sign(null.T @ np.array([-coef[1], coef[0]]))
    h = step if step is not None else opts.step
    for _ in range(6):
        u_new, _ = correct(problem, u + h * t_new, t_new, opts)
        if u_new is not None and np.linalg.norm(u_new - u) > 0.25 * h:
            forward = dataclasses.replace(opts, direction="forward")
            return _trace(problem, u_new, param, forward, t_new, callback, stop)
        h *= 0.5
    raise ConvergenceError(
        f"no new branch found at the branch point {param} = {p:.8g} (corrector failed or fell back)"
    )


def canonical_sign(v):
    """The unit vector along ``v`` whose largest component is positive, the first one of those
    within ``TIE`` of the largest in size: a rule of the direction itself, where the sign that the
    SVD gives depends on the LAPACK kernels (OpenBLAS picks them by the CPU). At a symmetry-breaking
    pitchfork it picks the same one of the two mirror-image branches on every machine, and at a
    period doubling the same one of the two copies a period apart (whose components are equal
    and opposite, hence the first)."""
    v = np.asarray(v, dtype=float) / np.linalg.norm(v)
    size = np.abs(v)
    first = int(np.flatnonzero(size >= (1.0 - TIE) * size.max())[0])
    return v if v[first] > 0 else -v


def _trace(problem, u0, param, opts, orient=None, callback=None, stop=None) -> Branch:
    runs = {}
    closed = False
    for forward in (True, False):
        if opts.direction == ("backward" if forward else "forward") or closed:
            continue
        start = make_point(problem, u0, initial_tangent(problem, u0, forward, orient))
        if runs:  # the same start as the other direction's: its stability is known
            first = next(iter(runs.values()))[0][0]
            start.eigenvalues, start.diagnostics = first.eigenvalues, first.diagnostics
        runs[forward] = _run(problem, start, opts, loop_guard=True, callback=callback, stop=stop)
        closed = runs[forward][1] == LOOP
    back, back_reason = runs.get(False, ([], None))
    ahead, ahead_reason = runs.get(True, ([], None))
    if back and ahead:
        if ahead[0].kind and not back[0].kind:  # the forward run ended at its first point
            back[0].kind, back[0].message, back[0].reason = ahead[0].kind, ahead[0].message, ahead[0].reason
        elif (
            not back[0].kind
            and len(back) > 1
            and len(ahead) > 1
            and abs(back[0].t[-1]) < 1e-6
            and not (back[1].kind or ahead[1].kind)
        ):
            # A start exactly at a fold: the runs leave it on the same side of p, so no step of
            # either run sees the sign change of t_p. The start point is the fold.
            if (back[1].u[-1] - back[0].u[-1]) * (ahead[1].u[-1] - ahead[0].u[-1]) > 0:
                back[0].kind, back[0].message = "LP", "fold at the start point"
        points = back[::-1] + ahead[1:]
    else:
        points = back[::-1] or ahead
    reasons = [r for r in (back_reason, ahead_reason) if r is not None]
    status = "ok" if all(r in COMPLETE for r in reasons) else next(r for r in reasons if r not in COMPLETE)
    ends = tuple((name, r) for name, r in (("backward", back_reason), ("forward", ahead_reason)) if r)
    message = "; ".join(f"{name}: {r}" for name, r in ends)
    resumed = [f"{q.u[-1]:.6g}" for q in points if q.refined]
    if resumed:
        message += f" (resumed with the finer problem after a stall at {param} = {', '.join(resumed)})"
    return _assemble(problem, points, param, status, message, opts, ends)


def _assemble(problem, points, param, status, message, opts, ends=()) -> Branch:
    u = np.array([q.u for q in points])
    steps = np.linalg.norm(np.diff(u, axis=0), axis=1)
    caps = capabilities(problem)
    for q in points:  # the ends appended last
        stamp(caps, q)
    eigenvalues = np.array([q.eigenvalues for q in points])
    stable = (
        np.array([caps.is_stable(ev) for ev in eigenvalues])
        if caps.has_stability
        else np.ones(len(points), dtype=bool)
    )
    names = sorted(set().union(*(q.diagnostics for q in points)))
    diagnostics = {k: np.array([q.diagnostics.get(k, np.nan) for q in points]) for k in names}
    special = tuple(
        SpecialPoint(
            q.kind,
            i,
            float(q.u[-1]),
            q.u[:-1].copy(),
            tuple(float(v) for v in q.bracket),
            q.message,
            q.t.copy(),
            q.located,
            q.reason,
            q.edge,
        )
        for i, q in enumerate(points)
        if q.kind
    )
    return Branch(
        param=param,
        names=tuple(problem.names),
        p=u[:, -1].copy(),
        x=u[:, :-1].copy(),
        stable=stable,
        eigenvalues=eigenvalues.astype(complex),
        newton_iterations=np.array([q.iterations for q in points]),
        arclength=np.concatenate([[0.0], np.cumsum(steps)]),
        special=special,
        status=status,
        message=message,
        options=dataclasses.asdict(opts),
        kind=caps.branch_kind,
        ends=tuple(ends),
        diagnostics=diagnostics,
    )
