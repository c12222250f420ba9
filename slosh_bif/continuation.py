"""Pseudo-arclength continuation (Keller), knowing nothing about sloshing.

A problem is any object with

* ``names`` - names of the n state components;
* ``residual(x, p)`` -> (n,), ``jacobian(x, p)`` -> (n, n), ``dparam(x, p)`` -> (n,);
* optionally ``in_domain(x, p)`` -> bool (points outside are never evaluated),
  ``edge_point(x, p)`` -> ``(x, p)`` or None: the exact point where the branch through (x, p)
  leaves the domain, appended as the branch's end when it gets there, and
  ``eigenvalues(x, p)`` -> (n,) complex (stable when all real parts are negative); a problem
  whose stability is that of its own Jacobian sets ``stability_from_jacobian = True`` instead,
  and the engine reuses the Jacobian it already has at each point; ``is_stable(eigenvalues)``
  -> bool replaces the default rule (all real parts negative), e.g. by Floquet multipliers;
  ``test_kinds`` (names) with ``test_functions(x, p)`` -> one real value per kind: further
  special points at sign changes, located like folds; ``confirm(kind, x, p)`` -> message, or
  None to drop a located point that is not what the kind means (e.g. a neutral saddle for NS).

With ``u = (x, p)`` and the unit tangent ``t`` of the curve F(u) = 0, each step predicts
``u + h t`` and corrects by Newton on the bordered system ``[F(u); t . (u - u_pred)] = 0``,
whose matrix ``[[F_x, F_p], [t^T]]`` stays regular through folds. The step h grows after easy
corrections and shrinks after slow or failed ones (or when a point leaves the domain), between
``step_min`` and ``step_max``.

Test functions along the branch: the parameter component of the tangent, ``t_p``, changes sign
at a fold (LP); the determinant of the bordered matrix changes sign at a simple branch point
(BP), and not at a fold. Both are located by Brent's method on the arclength from the last point
before the sign change, each evaluation a full corrector solve.

:func:`switch_branch` starts a new branch at a located branch point, along the direction of the
two-dimensional null space of ``[F_x, F_p]`` that the old branch does not take.

Each direction ends at a parameter bound (the end is computed on the bound), at the domain's
edge, on closing a loop, after ``max_steps``, or when the step falls below ``step_min``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize

from .branch import BRANCH_POINT, END, FOLD, Branch, SpecialPoint

__all__ = ["ContinuationOptions", "ConvergenceError", "continuation", "newton", "switch_branch"]

# End reasons of one direction; "ok" ones make a complete branch.
_BOUND, _EDGE, _LOOP = "parameter bound", "domain edge", "closed loop"
_STEPS, _STALL = "step limit", "step below minimum"
_COMPLETE = (_BOUND, _EDGE, _LOOP)


class ConvergenceError(RuntimeError):
    """The starting point could not be corrected onto the solution curve."""


@dataclasses.dataclass(frozen=True)
class ContinuationOptions:
    """Step control and tolerances; validated on construction (errors name the option).

    step, step_min, step_max : initial, smallest and largest arclength step
    max_steps : accepted steps per direction at most
    p_min, p_max : bounds of the continued parameter
    tol : Newton stops when |F| <= tol and the update <= tol * (1 + |u|)
    max_newton : corrector iterations before a step counts as failed
    growth : step factor after an easy step (<= 3 iterations)
    max_angle : the tangent may turn by about this much (radians) per step: the next step is
        scaled to it, and a step turning by more than twice as much is redone, so curves stay
        smooth through sharp peaks
    direction : "both", "forward" (increasing p at the start) or "backward"
    detect_folds, detect_branch_points : locate LP / BP
    locate_tol : arclength tolerance when locating a special point
    """

    step: float = 0.05
    step_min: float = 1e-9
    step_max: float = 0.5
    max_steps: int = 5000
    p_min: float = -math.inf
    p_max: float = math.inf
    tol: float = 1e-11
    max_newton: int = 12
    growth: float = 1.6
    max_angle: float = 0.1
    direction: str = "both"
    detect_folds: bool = True
    detect_branch_points: bool = True
    locate_tol: float = 1e-13

    def __post_init__(self):
        def need(ok, name, allowed):
            if not ok:
                raise ValueError(f"option {name} must be {allowed}; got {getattr(self, name)!r}")

        need(0 < self.step_min <= self.step <= self.step_max < math.inf, "step", "in [step_min, step_max], all positive and finite")
        need(isinstance(self.max_steps, int) and self.max_steps >= 1, "max_steps", "an integer >= 1")
        need(self.p_min < self.p_max, "p_min", "< p_max")
        need(0 < self.tol < 1e-2, "tol", "in (0, 1e-2)")
        need(isinstance(self.max_newton, int) and self.max_newton >= 2, "max_newton", "an integer >= 2")
        need(1 < self.growth <= 4, "growth", "in (1, 4]")
        need(0 < self.max_angle <= math.pi / 2, "max_angle", "in (0, pi/2]")
        need(self.direction in ("both", "forward", "backward"), "direction", "'both', 'forward' or 'backward'")
        need(0 < self.locate_tol < 1e-3, "locate_tol", "in (0, 1e-3)")


@dataclasses.dataclass
class _Point:
    u: np.ndarray
    t: np.ndarray
    iterations: int
    kind: str = ""
    message: str = ""
    bracket: tuple = ()
    tests: tuple = ()  # (fold test t_p, branch-point test det) at this point
    jac: np.ndarray | None = None  # F_x here, kept for stability


# -- linear algebra of the bordered system ---------------------------------------------------------


def _in_domain(problem, u):
    check = getattr(problem, "in_domain", None)
    return bool(np.all(np.isfinite(u))) and (check is None or bool(check(u[:-1], u[-1])))


def _top(problem, u):
    """F_x and the n x (n+1) matrix [F_x, F_p] at u."""
    x, p = u[:-1], u[-1]
    J = problem.jacobian(x, p)
    return J, np.column_stack([J, problem.dparam(x, p)])


def _bordered(problem, u, t):
    return np.vstack([_top(problem, u)[1], t])


def _solve(M, b):
    """Solve M z = b; at an exact branch point M is singular but the system consistent: least squares."""
    try:
        return np.linalg.solve(M, b)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(M, b, rcond=None)[0]


def _point(problem, u, t_prev, iterations=0, **extra):
    """A point at u with its unit tangent (oriented along t_prev) and test functions, from one F_x, F_p."""
    J, top = _top(problem, u)
    rhs = np.zeros(len(u))
    rhs[-1] = 1.0
    t = _solve(np.vstack([top, t_prev]), rhs)
    t /= np.linalg.norm(t)
    t = t if t @ t_prev >= 0 else -t
    tests = (t[-1], np.linalg.det(np.vstack([top, t])))
    if hasattr(problem, "test_functions"):
        tests += tuple(float(v) for v in problem.test_functions(u[:-1], u[-1]))
    return _Point(u, t, iterations, tests=tests, jac=J, **extra)


def _initial_tangent(problem, u, forward: bool, orient=None):
    t = np.linalg.svd(_top(problem, u)[1])[2][-1]  # null vector of [F_x, F_p]
    if orient is not None:
        t = t if t @ orient >= 0 else -t
    elif t[-1] < 0 or (t[-1] == 0 and t[0] < 0):
        t = -t
    return t if forward else -t


def _correct(problem, u_pred, t, opts):
    """Newton on [F(u); t . (u - u_pred)] = 0. Returns (u, iterations) or (None, iterations).

    Converged when |F| is at the tolerance and the last update, or the next one predicted from
    quadratic convergence (|du_k|^2 / |du_k-1|), is below ``tol * (1 + |u|)``.
    """
    u = u_pred.copy()
    step = previous = math.inf
    for k in range(opts.max_newton + 1):
        if not _in_domain(problem, u):
            return None, k
        F = problem.residual(u[:-1], u[-1])
        scale = 1.0 + np.linalg.norm(u)
        residual = np.linalg.norm(F)
        if k > 0 and residual <= max(opts.tol, 1e3 * np.finfo(float).eps * scale):
            if step <= opts.tol * scale or (k > 1 and step * step / previous <= opts.tol * scale):
                return u, k
            if k > 2 and residual <= 1e-2 * opts.tol:
                # Near a branch point the bordered matrix is nearly singular and the updates are
                # rounding noise amplified by its condition number; the residual still says done.
                return u, k
        if k == opts.max_newton:
            break
        du = _solve(_bordered(problem, u, t), -np.append(F, t @ (u - u_pred)))
        previous, step = step, np.linalg.norm(du)
        u = u + du
    return None, opts.max_newton


def newton(problem, x0, p, *, tol=1e-11, max_iter=30):
    """Newton at fixed parameter p from x0; raises :class:`ConvergenceError` with the reason."""
    x = np.asarray(x0, dtype=float).copy()
    for k in range(max_iter):
        if not _in_domain(problem, np.append(x, p)):
            raise ConvergenceError(f"Newton left the problem's domain at iteration {k} (x = {x}, p = {p})")
        F = problem.residual(x, p)
        if k == 0 and np.linalg.norm(F) <= 1e3 * np.finfo(float).eps * (1 + np.linalg.norm(x)):
            return x  # already a solution (e.g. a closed-form start): no step, no Jacobian needed
        try:
            dx = np.linalg.solve(problem.jacobian(x, p), -F)
        except np.linalg.LinAlgError:
            raise ConvergenceError(
                f"Newton at fixed p = {p}: the Jacobian F_x is singular at iteration {k} (x = {x}): a fold or branch point"
            ) from None
        x = x + dx
        if np.linalg.norm(dx) <= tol * (1 + np.linalg.norm(x)):
            return x
    raise ConvergenceError(f"Newton did not converge in {max_iter} iterations at p = {p} (last |F| = {np.linalg.norm(F):.3g})")


# -- location of special points --------------------------------------------------------------------


def _locate(problem, a: _Point, h, which, opts):
    """Brent on the arclength s in (0, h) from point a for a zero of test function ``which``.

    Returns (point, note). Exactly at a branch point the corrector's matrix is singular, and
    Brent may step so close that the correction fails: then the best point found so far is
    returned, with a note of how far from the zero it may be.
    """
    seen = {}

    def point(s):
        u, _ = _correct(problem, a.u + s * a.t, a.t, opts)
        if u is None:
            raise ConvergenceError("corrector failed while locating a special point")
        seen[s] = _point(problem, u, a.t)
        return seen[s]

    try:
        s = optimize.brentq(lambda s: point(s).tests[which], 0.0, h, xtol=opts.locate_tol, rtol=4 * np.finfo(float).eps)
        return point(s), ""
    except ConvergenceError:
        if not seen:
            raise
        left = [s for s in seen if np.sign(seen[s].tests[which]) == np.sign(a.tests[which])] + [0.0]
        right = [s for s in seen if s not in left] + [h]
        gap = min(right) - max(left)
        best = min(seen, key=lambda s: abs(seen[s].tests[which]))
        return seen[best], f" (located to within arclength {gap:.2g}: the corrector fails closer in)"


# -- one direction ---------------------------------------------------------------------------------


def _bound_message(bound, opts):
    return f"{_BOUND} {'p_max' if bound == opts.p_max else 'p_min'} = {bound}"


def _end_on_bound(problem, a: _Point, b_u, bound, opts):
    """The point with p = bound between a and the overshooting b_u (Newton at fixed p)."""
    w = (bound - a.u[-1]) / (b_u[-1] - a.u[-1])
    try:
        x = newton(problem, (1 - w) * a.u[:-1] + w * b_u[:-1], bound, tol=opts.tol)
    except (ConvergenceError, np.linalg.LinAlgError):
        x = (1 - w) * a.u[:-1] + w * b_u[:-1]  # a fold on the bound: keep the interpolated point
    u = np.append(x, bound)
    return _point(problem, u, a.t, kind=END, message=_bound_message(bound, opts), bracket=(a.u[-1], b_u[-1]))


def _run(problem, start: _Point, opts, loop_guard: bool, callback=None):
    points = [start]
    h = opts.step
    edge_hits = 0
    while True:
        if len(points) > opts.max_steps:
            points[-1].kind, points[-1].message = END, f"{_STEPS} ({opts.max_steps} steps)"
            return points, _STEPS
        a = points[-1]
        u, iters = _correct(problem, a.u + h * a.t, a.t, opts)
        if u is None:
            edge_hits += not _in_domain(problem, a.u + h * a.t) or iters < opts.max_newton
            h *= 0.5
            if h < opts.step_min:
                reason = _EDGE if edge_hits else _STALL
                bracket = (a.u[-1], (a.u + 2 * h * a.t)[-1])
                edge = _edge_point(problem, a, opts) if reason == _EDGE else None
                if edge is not None:
                    points.append(_Point(edge, a.t, 0, END, f"{reason}: {getattr(problem, 'edge_name', 'boundary')}", bracket, a.tests))
                else:
                    a.kind, a.message, a.bracket = END, f"{reason}: last step {2 * h:.3g} failed", bracket
                return points, reason
            continue
        edge_hits = 0
        if not opts.p_min <= u[-1] <= opts.p_max:
            bound = opts.p_max if u[-1] > opts.p_max else opts.p_min
            if a.u[-1] == bound:  # a start on the bound is itself the end (not a second copy of it)
                a.kind, a.message = END, _bound_message(bound, opts)
            else:
                points.append(_end_on_bound(problem, a, u, bound, opts))
            return points, _BOUND
        b = _point(problem, u, a.t, iters)
        angle = math.acos(min(1.0, max(-1.0, float(b.t @ a.t))))
        if angle > 2 * opts.max_angle and h > 2 * opts.step_min:
            h *= 0.5 * opts.max_angle / angle + 0.25  # turned far too sharply: redo shorter
            continue
        points.extend(_special_between(problem, a, b, h, opts))
        points.append(b)
        if callback is not None:
            callback(float(u[-1]), u[:-1])
        if loop_guard and len(points) > 3 and _passes(start, a.u, u, h):
            b.kind, b.message = END, f"{_LOOP}: back at the start point"
            return points, _LOOP
        h = min(h * opts.growth, opts.step_max) if iters <= 3 else (h * 0.6 if iters >= 6 else h)
        if angle > opts.max_angle:
            h *= opts.max_angle / angle
        h = max(h, opts.step_min)


def _edge_point(problem, a: _Point, opts):
    """The problem's exact edge point near a, if it offers one within the parameter bounds."""
    hook = getattr(problem, "edge_point", None)
    edge = hook(a.u[:-1], a.u[-1]) if hook else None
    if edge is None:
        return None
    u = np.append(edge[0], edge[1])
    return u if opts.p_min <= u[-1] <= opts.p_max and np.all(np.isfinite(u)) else None


def _passes(start: _Point, ua, ub, h):
    """Whether the step from ua to ub runs through the start point in the start's direction."""
    seg = ub - ua
    w = np.clip((start.u - ua) @ seg / (seg @ seg), 0.0, 1.0)
    return np.linalg.norm(ua + w * seg - start.u) < 0.1 * h and seg @ start.t > 0


_TEST_MEANING = {
    FOLD: "fold: the tangent's parameter component changes sign",
    BRANCH_POINT: "branch point: the bordered Jacobian's determinant changes sign",
}


def _special_between(problem, a: _Point, b: _Point, h, opts):
    found = []
    tests = [(0, FOLD, opts.detect_folds), (1, BRANCH_POINT, opts.detect_branch_points)]
    tests += [(2 + i, kind, True) for i, kind in enumerate(getattr(problem, "test_kinds", ()))]
    confirm = getattr(problem, "confirm", None)
    for which, kind, enabled in tests:
        if enabled and np.sign(a.tests[which]) * np.sign(b.tests[which]) < 0:
            try:
                q, note = _locate(problem, a, h, which, opts)
            except (ConvergenceError, ValueError) as err:
                q = dataclasses.replace(b, iterations=0)
                q.message = f"{kind} detected, not located: {err}"
            else:
                q.message = _TEST_MEANING.get(kind, f"{kind}: test function changes sign")
                if confirm is not None and which >= 2:
                    q.message = confirm(kind, q.u[:-1], q.u[-1])
                    if q.message is None:
                        continue
                q.message += note
            q.kind, q.bracket = kind, (a.u[-1], b.u[-1])
            found.append(q)
    found.sort(key=lambda q: (q.u - a.u) @ a.t)
    return found


# -- the driver ------------------------------------------------------------------------------------


def continuation(problem, x0, p0, *, param="p", options: ContinuationOptions | None = None, orient=None, callback=None) -> Branch:
    """Trace the solution curve of ``problem`` through ``(x0, p0)``; returns a :class:`Branch`.

    ``x0`` is corrected at fixed ``p0`` first, or, where that is singular (a start at a fold),
    along the branch's tangent (a :class:`ConvergenceError` says why when neither works). Mid-branch failures do not raise: the branch ends there with the reason.
    ``orient`` (a vector in (x, p)) makes "forward" the direction along it instead of along
    increasing p (needed where the branch runs across the parameter, as after a pitchfork).
    ``callback(p, x)``, if given, is called after every accepted point (for progress reports).
    """
    opts = options or ContinuationOptions()
    if not opts.p_min <= p0 <= opts.p_max:
        raise ValueError(f"start parameter {param} = {p0} lies outside [p_min, p_max] = [{opts.p_min}, {opts.p_max}]")
    x0 = np.atleast_1d(np.asarray(x0, dtype=float))
    if len(x0) != len(problem.names) or not np.all(np.isfinite(x0)):
        raise ValueError(f"x0 must be {len(problem.names)} finite numbers ({', '.join(problem.names)}); got {x0}")
    try:
        u0 = np.append(newton(problem, x0, p0, tol=opts.tol), p0)
    except ConvergenceError as err:
        # At (or very near) a fold F_x is singular and Newton at fixed p fails; the bordered
        # corrector along the tangent of [F_x, F_p] is regular there (p may move a little).
        guess = np.append(x0, p0)
        u0, _ = _correct(problem, guess, _initial_tangent(problem, guess, True), opts)
        if u0 is None:
            raise ConvergenceError(f"{err}; the pseudo-arclength corrector from the same point failed too") from None
    return _trace(problem, u0, param, opts, orient, callback)


def switch_branch(problem, point, *, param="p", options: ContinuationOptions | None = None, along=None, step=None, callback=None) -> Branch:
    """The branch that crosses the old one at a located branch point, traced away from it.

    ``point`` is a :class:`SpecialPoint` (or an ``(x, p)`` pair) at a simple branch point of
    ``problem``: the null space of ``[F_x, F_p]`` there is two-dimensional. ``along`` is the old
    branch's tangent (or any vector in that null space to avoid); the new direction is the null
    vector orthogonal to it. The first point is ``u_BP + step * t_new`` corrected on the
    hyperplane through it normal to t_new; the branch is traced forward from there (away from
    the branch point; the part behind it is, for a symmetry-breaking pitchfork, the mirror image).
    Raises :class:`ConvergenceError` when no new branch is found.
    """
    if along is None:
        raise ValueError("switch_branch needs along= (the old branch's tangent at the branch point)")
    opts = options or ContinuationOptions()
    x, p = (point.x, point.p) if hasattr(point, "x") else point
    u = np.append(np.asarray(x, dtype=float), float(p))
    null = np.linalg.svd(_top(problem, u)[1])[2][-2:]  # the two smallest right singular vectors
    coef = null @ np.asarray(along, dtype=float)  # the old direction, in the null space's basis
    t_new = null.T @ np.array([-coef[1], coef[0]])
    t_new /= np.linalg.norm(t_new)
    h = step if step is not None else opts.step
    for _ in range(6):
        u_new, _ = _correct(problem, u + h * t_new, t_new, opts)
        if u_new is not None and np.linalg.norm(u_new - u) > 0.25 * h:
            return _trace(problem, u_new, param, dataclasses.replace(opts, direction="forward"), t_new, callback)
        h *= 0.5
    raise ConvergenceError(f"no new branch found at the branch point {param} = {p:.8g} (corrector failed or fell back)")


def _trace(problem, u0, param, opts, orient=None, callback=None) -> Branch:
    runs = {}
    closed = False
    for forward in (True, False):
        if opts.direction == ("backward" if forward else "forward") or closed:
            continue
        start = _point(problem, u0, _initial_tangent(problem, u0, forward, orient))
        runs[forward] = _run(problem, start, opts, loop_guard=True, callback=callback)
        closed = runs[forward][1] == _LOOP
    back, back_reason = runs.get(False, ([], None))
    ahead, ahead_reason = runs.get(True, ([], None))
    if back and ahead:
        if ahead[0].kind and not back[0].kind:  # the forward run ended at its first point
            back[0].kind, back[0].message = ahead[0].kind, ahead[0].message
        elif not back[0].kind and len(back) > 1 and len(ahead) > 1 and abs(back[0].t[-1]) < 1e-6 and not (back[1].kind or ahead[1].kind):
            # A start exactly at a fold: the runs leave it on the same side of p, so no step of
            # either run sees the sign change of t_p. The start point is the fold.
            if (back[1].u[-1] - back[0].u[-1]) * (ahead[1].u[-1] - ahead[0].u[-1]) > 0:
                back[0].kind, back[0].message = "LP", "fold at the start point"
        points = back[::-1] + ahead[1:]
    else:
        points = back[::-1] or ahead
    reasons = [r for r in (back_reason, ahead_reason) if r is not None]
    status = "ok" if all(r in _COMPLETE for r in reasons) else next(r for r in reasons if r not in _COMPLETE)
    message = "; ".join(f"{name}: {r}" for name, r in (("backward", back_reason), ("forward", ahead_reason)) if r)
    return _assemble(problem, points, param, status, message, opts)


def _eigenvalues(problem, q: _Point):
    n = len(q.u) - 1
    if getattr(problem, "stability_from_jacobian", False):
        J = q.jac if q.jac is not None else problem.jacobian(q.u[:-1], q.u[-1])
        return np.linalg.eigvals(J) if np.all(np.isfinite(J)) else np.full(n, np.nan + 0j)
    if hasattr(problem, "eigenvalues"):
        return problem.eigenvalues(q.u[:-1], q.u[-1])
    return np.full(n, np.nan + 0j)


def _assemble(problem, points, param, status, message, opts) -> Branch:
    u = np.array([q.u for q in points])
    steps = np.linalg.norm(np.diff(u, axis=0), axis=1)
    eigenvalues = np.array([_eigenvalues(problem, q) for q in points])
    given = getattr(problem, "stability_from_jacobian", False) or hasattr(problem, "eigenvalues")
    rule = getattr(problem, "is_stable", lambda ev: bool(np.all(ev.real < 0)))
    stable = np.array([rule(ev) for ev in eigenvalues]) if given else np.ones(len(points), dtype=bool)
    special = tuple(
        SpecialPoint(q.kind, i, float(q.u[-1]), q.u[:-1].copy(), tuple(float(v) for v in q.bracket), q.message)
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
    )
