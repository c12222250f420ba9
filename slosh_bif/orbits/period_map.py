"""Periodic orbits of any forced vector field by single shooting: the period map phi_T and its Newton.

The forcing has period T, so a periodic orbit is a fixed point of the period map (no phase
condition): Newton on ``F(y0) = phi_T(y0) - y0`` with ``DF = M - I``, the monodromy matrix M
integrated with the orbit from the variational equations by scipy. This is the reference path for
any ``rhs(tau, y)``, ``jac(tau, y)``; the compiled multiple shooting of (9) is
:mod:`slosh_bif.orbits.shooting`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation.corrector import newton_solve

__all__ = ["PeriodicOrbit", "period_map", "shoot"]


@dataclasses.dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found by shooting (or the last iterate, with ``converged`` False).

    Attributes
    ----------
    y0 : (n,) state at tau = 0;  period : T;  monodromy : (n, n) matrix M
    multipliers : (n,) Floquet multipliers (eigenvalues of M), largest modulus first
    stable : all multipliers strictly inside the unit circle
    liouville_error : |det M - exp(int tr J)| / exp(int tr J), the built-in accuracy check
    residual : |phi_T(y0) - y0|;  iterations : Newton steps;  converged, message : the outcome
    """

    y0: np.ndarray
    period: float
    monodromy: np.ndarray
    multipliers: np.ndarray
    stable: bool
    liouville_error: float
    residual: float
    iterations: int
    converged: bool
    message: str


def period_map(rhs, jac, y0, period, *, tau0=0.0, rtol=1e-10, atol=1e-12, method="DOP853"):
    """phi_T(y0), the monodromy M and int tr J over [tau0, tau0 + T], from one integration.

    The augmented state is ``[y, Phi (row-major), int tr J]``.
    """
    y0 = np.asarray(y0, dtype=float)
    n = len(y0)

    def augmented(tau, z):
        y, Phi = z[:n], z[n : n + n * n].reshape(n, n)
        J = jac(tau, y)
        return np.concatenate([rhs(tau, y), (J @ Phi).ravel(), [np.trace(J)]])

    z0 = np.concatenate([y0, np.eye(n).ravel(), [0.0]])
    from scipy.integrate import solve_ivp  # the reference path only

    with np.errstate(over="ignore", invalid="ignore"):  # trial steps deep in the wall may overflow
        sol = solve_ivp(augmented, (tau0, tau0 + period), z0, method=method, rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"integration over one period failed: {sol.message}")
    z = sol.y[:, -1]
    return z[:n], z[n : n + n * n].reshape(n, n), z[-1]


class _PeriodMapProblem:
    """phi_T(y) - y of any vector field as a problem for :func:`newton_solve` (one integration
    per iterate serves the residual, the Jacobian M - I and the multipliers)."""

    def __init__(self, rhs, jac, period, **integration):
        self.rhs, self.jac, self.period, self.integration = rhs, jac, period, integration
        self._last = (None, None)

    def map(self, y):
        if self._last[0] is None or not np.array_equal(self._last[0], y):
            self._last = (y.copy(), period_map(self.rhs, self.jac, y, self.period, **self.integration))
        return self._last[1]

    def residual(self, y, _p):
        return self.map(y)[0] - y

    def jacobian(self, y, _p):
        return self.map(y)[1] - np.eye(len(y))


def shoot(
    rhs, jac, y0, period, *, tol=1e-10, max_iter=20, rtol=1e-10, atol=1e-12, method="DOP853"
) -> PeriodicOrbit:
    """Newton on phi_T(y0) - y0 = 0. Never raises on non-convergence: the result says why."""
    y = np.asarray(y0, dtype=float).copy()
    if not np.all(np.isfinite(y)):
        raise ValueError(f"initial guess must be finite; got {y0!r}")
    problem = _PeriodMapProblem(rhs, jac, period, rtol=rtol, atol=atol, method=method)
    run = newton_solve(problem, y, 0.0, tol=tol, max_iter=max_iter, criterion="residual")
    _, M, trace_integral = problem.map(run.x)
    multipliers = np.linalg.eigvals(M)
    multipliers = multipliers[np.argsort(-np.abs(multipliers))]
    expected = np.exp(trace_integral)
    return PeriodicOrbit(
        y0=run.x,
        period=float(period),
        monodromy=M,
        multipliers=multipliers,
        stable=bool(np.all(np.abs(multipliers) < 1)),
        liouville_error=float(abs(np.linalg.det(M) - expected) / expected),
        residual=run.residual,
        iterations=run.iterations,
        converged=run.converged,
        message=run.message,
    )
