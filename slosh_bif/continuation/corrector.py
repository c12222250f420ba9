"""The bordered system of pseudo-arclength continuation and its Newton correctors.

With ``u = (x, p)`` and the unit tangent ``t`` of the curve F(u) = 0, a predicted point is
corrected by Newton on ``[F(u); t . (u - u_pred)] = 0``, whose matrix ``[[F_x, F_p], [t^T]]``
stays regular through folds. :func:`newton` is the plain corrector at fixed parameter.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.continuation.problem import capabilities
from slosh_bif.newton import NewtonResult, NewtonSettings, newton_loop

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
    J, M = _bordered(problem, u)
    return J, M[:-1]


def _bordered(problem, u):
    """F_x at u and the (n+1) x (n+1) matrix [[F_x, F_p], [0]] whose last row is left for a tangent."""
    x, p = u[:-1], u[-1]
    J = problem.jacobian(x, p)
    n = len(x)
    M = np.zeros((n + 1, n + 1), dtype=np.result_type(J, float))
    M[:n, :n] = J
    M[:n, n] = problem.dparam(x, p)
    return J, M


def bordered(problem, u, t):
    M = _bordered(problem, u)[1]
    M[-1] = t
    return M


def solve(M, b):
    """Solve M z = b; at an exact branch point M is singular but the system consistent: least squares."""
    try:
        return np.linalg.solve(M, b)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(M, b, rcond=None)[0]


def make_point(problem, u, t_prev, iterations=0, **extra):
    """A point at u with its unit tangent (oriented along t_prev) and test functions, from one F_x, F_p."""
    J, M = _bordered(problem, u)
    rhs = np.zeros(len(u))
    rhs[-1] = 1.0
    M[-1] = t_prev
    t = solve(M, rhs)
    t /= np.linalg.norm(t)
    t = t if t @ t_prev >= 0 else -t
    M[-1] = t
    tests = (t[-1], np.linalg.det(M)) + capabilities(problem).tests(u[:-1], u[-1])
    return Point(u, t, iterations, tests=tests, jac=J, **extra)


def initial_tangent(problem, u, forward: bool, orient=None):
    t = np.linalg.svd(top_rows(problem, u)[1])[2][-1]  # null vector of [F_x, F_p]
    if orient is not None:
        t = t if t @ orient >= 0 else -t
    elif t[-1] < 0 or (t[-1] == 0 and t[0] < 0):
        t = -t
    return t if forward else -t


def correct(problem, u_pred, t, opts, *, strict: bool = False):
    """Newton on [F(u); t . (u - u_pred)] = 0 (:func:`~slosh_bif.newton.newton_loop` at
    ``opts.tol``, its ``"lookahead"`` rule, or with ``strict`` its ``"corrector"`` rule, which
    takes one more evaluation to converge further: for located special points). Returns
    (u, iterations) or (None, iterations)."""
    run = newton_loop(
        lambda u: np.append(problem.residual(u[:-1], u[-1]), t @ (u - u_pred)),
        lambda u: bordered(problem, u, t),
        u_pred,
        NewtonSettings(
            tol=opts.tol, max_iter=opts.max_newton, criterion="corrector" if strict else "lookahead"
        ),
        admissible=lambda u: in_domain(problem, u),
        solve=solve,
    )
    if run.converged:
        return run.x, run.iterations
    # a run stopped for lack of progress counts as one that spent its updates (the engine reads
    # a failure in fewer as the domain's edge)
    return None, opts.max_newton if run.stalled else run.iterations


def newton_solve(
    problem, x0, p, *, tol=1e-11, max_iter=30, criterion: str = "step", halvings: int = 0
) -> NewtonResult:
    """Newton on ``problem.residual(x, p) = 0`` at fixed p from x0 (:func:`~slosh_bif.newton.newton_loop`);
    never raises on failure. ``criterion``: ``"step"`` or ``"residual"``
    (:data:`~slosh_bif.newton.CRITERIA`); a step that leaves the problem's domain is halved up to
    ``halvings`` times."""
    if criterion not in ("step", "residual"):
        raise ValueError(f"criterion must be 'step' or 'residual'; got {criterion!r}")
    return newton_loop(
        lambda x: problem.residual(x, p),
        lambda x: problem.jacobian(x, p),
        x0,
        NewtonSettings(tol=tol, max_iter=max_iter, criterion=criterion, halvings=halvings),
        admissible=lambda x: in_domain(problem, np.append(x, p)),
        domain=f"the problem's domain at p = {p}",
    )


def newton(problem, x0, p, *, tol=1e-11, max_iter=30):
    """Newton at fixed parameter p from x0 (:func:`newton_solve`); the solution x, or
    :class:`ConvergenceError` with the reason."""
    run = newton_solve(problem, x0, p, tol=tol, max_iter=max_iter)
    if not run.converged:
        raise ConvergenceError(f"Newton at fixed p = {p}: {run.message}")
    return run.x
