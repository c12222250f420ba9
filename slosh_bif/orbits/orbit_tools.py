"""One periodic orbit of (9) at a time, without continuation: Newton on the shooting system from a
guess (periodic_orbit, orbit_at), the measures a branch records at each orbit (amplitudes,
first harmonics, impact speeds: orbit_measures), and the symmetry of an orbit read off its arcs'
start states (y(tau + T/2) = -y(tau), as (9) under the forcing's half-period shift:
half_period_gap, is_symmetric, symmetrized)."""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.model.params import Params
from slosh_bif.orbits.period_map import PeriodicOrbit
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = [
    "half_period_gap",
    "is_symmetric",
    "symmetrized",
    "orbit_at",
    "orbit_measures",
    "periodic_orbit",
]


def orbit_measures(problem: ShootingProblem, x, p, *, points_per_2pi: int = 512) -> dict:
    """A1 (first-harmonic amplitude of X at the forcing frequency), max |X|, max |w| and the
    symmetry defect |y(tau + pi) + y(tau)| of the orbit through x (0 for a symmetric orbit)."""
    taus, Y = problem.orbit(x, p, points_per_2pi=points_per_2pi)
    X = Y[:-1, 0]
    coef = np.fft.rfft(X)[problem.period_multiple] * 2 / len(X)  # the forcing frequency's bin
    half = points_per_2pi // 2  # tau = pi
    # A mirrored symmetric orbit (see ShootingProblem.orbit) has the defect |y(pi) + y(0)|, G's residual.
    defect = float(
        np.max(np.abs(Y[half : half + points_per_2pi + 1 - half] + Y[: points_per_2pi + 1 - half]))
    )
    return {
        "A1": float(abs(coef)),
        "max_abs_X": float(np.max(np.abs(Y[:, 0]))),
        "max_abs_w": float(np.max(np.abs(Y[:, 2]))),
        "symmetry_defect": float(defect),
    }


def periodic_orbit(
    params: Params,
    y0,
    *,
    segments: int = 1,
    tol=1e-10,
    max_iter=20,
    rtol=1e-10,
    atol=1e-12,
    backend: str = "auto",
) -> PeriodicOrbit:
    """The 2pi-periodic orbit of the smooth model (9) nearest the guess ``y0 = [X, X', w, w']``.

    Newton on the (multiple-)shooting residual of :class:`ShootingProblem`; never raises on
    non-convergence (the result says why).
    """
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise ValueError(f"initial guess must be finite [X, X', w, w']; got {y0!r}")
    problem = ShootingProblem(params, segments=segments, rtol=rtol, atol=atol, backend=backend)
    return orbit_at(problem, problem.initial_states(y0), params.sigma, tol=tol, max_iter=max_iter)


def orbit_at(problem: ShootingProblem, x, p, *, tol=1e-10, max_iter=20) -> PeriodicOrbit:
    """Newton on ``problem`` at fixed parameter p from x; the orbit with multipliers and checks."""
    run = newton_solve(problem, x, p, tol=tol, max_iter=max_iter, criterion="residual")
    x = run.x
    # Multipliers and checks of a converged orbit only: a failed run's last iterate may never have
    # been integrated (Newton stopped as it left the domain) and can lie deep in the wall, where
    # one integration of its arcs took minutes (the critical forcing at sigma = 4, Fig. 10 set).
    finite = run.converged and bool(np.isfinite(run.residual))
    mu = problem.eigenvalues(x, p) if finite else np.full(4, np.nan + 0j)
    return PeriodicOrbit(
        y0=x[:4].copy(),
        period=problem.orbit_period,
        monodromy=problem.monodromy(x, p) if finite else np.full((4, 4), np.nan),
        multipliers=mu,
        stable=problem.is_stable(mu),
        liouville_error=problem.liouville_error(x, p) if finite else np.nan,
        residual=run.residual,
        iterations=run.iterations,
        converged=run.converged,
        message=run.message,
    )


def is_symmetric(problem: ShootingProblem, x, tol: float = 1e-3) -> bool:
    """Whether the orbit x of a whole-period problem (an odd number of forcing periods in an even
    number of equal arcs) is symmetric to ``tol``: half its period later the state is its
    negative, as the forcing is. Where an asymmetric branch turns or has a branch point at such an
    orbit, its pair meets the symmetric parent there (the parent's pitchfork)."""
    if problem.period_multiple % 2 == 0:
        return False
    return half_period_gap(problem, x, -1.0) <= tol


def half_period_gap(problem: ShootingProblem, x, sign: float) -> float:
    """|x(T/2) - sign x(0)| over the orbit's arcs relative to 1 + |x| (inf where the arcs do not
    split the period in halves)."""
    m = problem.segments
    if m % 2 or problem.symmetric:
        return np.inf
    states = np.asarray(x, dtype=float)[: 4 * m].reshape(m, 4)
    return float(np.linalg.norm(states[m // 2 :] - sign * states[: m // 2]) / (1 + np.linalg.norm(states)))


def symmetrized(x) -> np.ndarray:
    """The states x of a whole-period orbit at the starts of an even number of arcs made exactly
    symmetric, x(T/2) = -x(0): the mean of the first half and the second half's negative (for an
    orbit symmetric to its location's accuracy, where an asymmetric pair meets its parent)."""
    x = np.asarray(x, dtype=float)
    half = 0.5 * (x[: len(x) // 2] - x[len(x) // 2 :])
    return np.concatenate([half, -half])
