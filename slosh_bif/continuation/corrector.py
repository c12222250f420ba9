"""The bordered system of pseudo-arclength continuation and its Newton correctors.

With ``u = (x, p)`` and the unit tangent ``t`` of the curve F(u) = 0, a predicted point is
corrected by Newton on ``[F(u); t . (u - u_pred)] = 0``, whose matrix ``[[F_x, F_p], [t^T]]``
stays regular through folds. :func:`newton` is the plain corrector at fixed parameter.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.continuation.problem import capabilities

__all__ = [
    "Point",
    "NewtonResult",
    "in_domain",
    "top_rows",
    "bordered",
    "solve",
    "make_point",
    "initial_tangent",
    "correct",
    "newton",
    "newton_solve",
]


@dataclasses.dataclass
class Point:
    u: np.ndarray
    t: np.ndarray
    iterations: int
    kind: str = ""
    message: str = ""
    bracket: tuple = ()
    tests: tuple = ()  # (fold test t_p, branch-point test det) at this point
    jac: np.ndarray | None = None  # F_x here, kept for stability
    located: bool = True  # False: a sign change seen but not located (the point is the nearest computed one)
    reason: str = ""  # an END point's reason (a Status value)
    edge: str = ""  # at a domain edge: the problem's name for it
    eigenvalues: np.ndarray | None = None  # stability, computed once when the point joins the branch
    diagnostics: dict | None = None  # the problem's per-point checks (e.g. Liouville's), likewise
    refined: bool = False  # a stalled direction was resumed here with the problem's finer version


def in_domain(problem, u):
    return capabilities(problem).in_domain(u)


def top_rows(problem, u):
    """F_x and the n x (n+1) matrix [F_x, F_p] at u."""
    x, p = u[:-1], u[-1]
    J = problem.jacobian(x, p)
    return J, np.column_stack([J, problem.dparam(x, p)])


def bordered(problem, u, t):
    return np.vstack([top_rows(problem, u)[1], t])


def solve(M, b):
    """Solve M z = b; at an exact branch point M is singular but the system consistent: least squares."""
    try:
        return np.linalg.solve(M, b)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(M, b, rcond=None)[0]


def make_point(problem, u, t_prev, iterations=0, **extra):
    """A point at u with its unit tangent (oriented along t_prev) and test functions, from one F_x, F_p."""
    J, top = top_rows(problem, u)
    rhs = np.zeros(len(u))
    rhs[-1] = 1.0
    t = solve(np.vstack([top, t_prev]), rhs)
    t /= np.linalg.norm(t)
    t = t if t @ t_prev >= 0 else -t
    tests = (t[-1], np.linalg.det(np.vstack([top, t]))) + capabilities(problem).tests(u[:-1], u[-1])
    return Point(u, t, iterations, tests=tests, jac=J, **extra)


def initial_tangent(problem, u, forward: bool, orient=None):
    t = np.linalg.svd(top_rows(problem, u)[1])[2][-1]  # null vector of [F_x, F_p]
    if orient is not None:
        t = t if t @ orient >= 0 else -t
    elif t[-1] < 0 or (t[-1] == 0 and t[0] < 0):
        t = -t
    return t if forward else -t


def correct(problem, u_pred, t, opts):
    """Newton on [F(u); t . (u - u_pred)] = 0. Returns (u, iterations) or (None, iterations).

    Converged when |F| is at the tolerance and the last update, or the next one predicted from
    quadratic convergence (|du_k|^2 / |du_k-1|), is below ``tol * (1 + |u|)``.
    """
    u = u_pred.copy()
    step = previous = math.inf
    for k in range(opts.max_newton + 1):
        if not in_domain(problem, u):
            return None, k
        F = problem.residual(u[:-1], u[-1])
        if not np.all(
            np.isfinite(F)
        ):  # an evaluation failed (an integration, say): the step is cut, no Jacobian is formed
            return None, k
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
        du = solve(bordered(problem, u, t), -np.append(F, t @ (u - u_pred)))
        previous, step = step, np.linalg.norm(du)
        u = u + du
    return None, opts.max_newton


@dataclasses.dataclass(frozen=True)
class NewtonResult:
    """The outcome of Newton at a fixed parameter: the last iterate, whether it converged, the
    iterations taken, the last residual norm and a message saying why it stopped."""

    x: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str


def newton_solve(problem, x0, p, *, tol=1e-11, max_iter=30, criterion: str = "step") -> NewtonResult:
    """Newton on ``problem.residual(x, p) = 0`` at fixed p from x0; never raises on failure.

    ``criterion="step"``: converged when the update is below ``tol (1 + |x|)`` (or the start is a
    solution to rounding); ``"residual"``: when ``|F| <= tol (1 + |x|)`` (for residuals that carry
    an integration's error, whose updates stall at that error).
    """
    if criterion not in ("step", "residual"):
        raise ValueError(f"criterion must be 'step' or 'residual'; got {criterion!r}")
    x = np.asarray(x0, dtype=float).copy()
    F = np.full(len(x), np.nan)

    def result(converged, k, message):
        residual = float(np.linalg.norm(F)) if np.all(np.isfinite(F)) else math.inf
        return NewtonResult(x, converged, k, residual, message)

    for k in range(max_iter + 1):
        if not in_domain(problem, np.append(x, p)):
            return result(False, k, f"Newton left the problem's domain at iteration {k} (x = {x}, p = {p})")
        F = problem.residual(x, p)
        if not np.all(np.isfinite(F)):
            return result(
                False, k, "the residual is not finite (an integration failed): no solution near this guess"
            )
        scale = 1 + np.linalg.norm(x)
        if criterion == "residual" and np.linalg.norm(F) <= tol * scale:
            return result(True, k, f"converged in {k} Newton steps")
        if criterion == "step" and k == 0 and np.linalg.norm(F) <= 1e3 * np.finfo(float).eps * scale:
            return result(
                True, 0, "the start is a solution"
            )  # e.g. a closed form: no step, no Jacobian needed
        if k == max_iter:
            break
        try:
            dx = np.linalg.solve(problem.jacobian(x, p), -F)
        except np.linalg.LinAlgError:
            return result(False, k, f"the Jacobian F_x is singular at iteration {k}: a fold or branch point")
        x = x + dx
        if not np.all(np.isfinite(x)):
            return result(False, k + 1, "Newton diverged (non-finite iterate)")
        if criterion == "step" and np.linalg.norm(dx) <= tol * (1 + np.linalg.norm(x)):
            return result(True, k + 1, f"converged in {k + 1} Newton steps")
    return result(
        False, max_iter, f"no convergence in {max_iter} Newton steps (last |F| = {np.linalg.norm(F):.3g})"
    )


def newton(problem, x0, p, *, tol=1e-11, max_iter=30):
    """Newton at fixed parameter p from x0 (:func:`newton_solve`); the solution x, or
    :class:`ConvergenceError` with the reason."""
    run = newton_solve(problem, x0, p, tol=tol, max_iter=max_iter)
    if not run.converged:
        raise ConvergenceError(f"Newton at fixed p = {p}: {run.message}")
    return run.x
