"""The model's side of a frequency-response fit: every steady state of the slow flow (45) at a
given sigma, with its stability, from the steady-state equation (46).

For a fixed amplitude A, (46) is quadratic in sigma: its two roots, low and high
(:func:`~slosh_bif.slowflow.steady_states.sigma_on_curve`), trace the whole response curve. The
steady states at one sigma are the amplitudes where either root equals it, bracketed on a log grid of A
over S+ and refined by Brent; each is stable when the Jacobian of (45) there has both eigenvalues
in the left half-plane (the middle branch of a hysteresis loop is a saddle; a Hopf point bounds
the strongly modulated response).

Below S+'s end the particle need not reach the walls at all: the impact-free response of (8)'s
linear flight, Y = (i - K)^-1 F (X = Re Y e^(i tau)), is a steady state too, stable (a damped
linear motion) wherever its |w| stays below the wall, |Y_w| < 1 (:func:`impact_free`): the
non-resonant response a sweep jumps from and to.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import optimize

from slosh_bif.model.equations import ImpactModel
from slosh_bif.model.params import Params
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.slowflow.steady_states import sigma_on_curve

__all__ = ["ResponseCurve", "response_curve", "impact_free", "impact_free_state"]

GRID = 800  # amplitudes on S+ where the roots are bracketed
_EDGE = 2e-8  # relative margin from the manifold's ends (alpha has a square root there)
_TURN = 1e-12  # a discriminant of (46) this far below zero (relative) is the curve's turn


@dataclasses.dataclass(frozen=True)
class ResponseCurve:
    """The response curve of one parameter set: its amplitude grid ``A`` and both roots of (46)
    there (``sigma_low``, ``sigma_high``, NaN where no steady state has that amplitude)."""

    flow: SlowFlow
    A: np.ndarray
    sigma_low: np.ndarray
    sigma_high: np.ndarray

    def states_at(self, sigma: float) -> list:
        """(A, stable) of every steady state at ``sigma``, by increasing A."""
        found = []
        for k, branch in enumerate((self.sigma_low, self.sigma_high)):
            g = branch - sigma
            ok = np.isfinite(g[:-1]) & np.isfinite(g[1:])
            for i in np.flatnonzero(ok & (np.sign(g[:-1]) * np.sign(g[1:]) <= 0)):
                if g[i] == 0.0 and i > 0 and ok[i - 1] and g[i - 1] != 0.0:
                    continue  # a root on a grid point, found from the interval before
                A = optimize.brentq(
                    lambda a: sigma_on_curve(self.flow, a, rounding=_TURN)[k] - sigma,
                    self.A[i],
                    self.A[i + 1],
                    xtol=1e-13,
                    rtol=4 * np.finfo(float).eps,
                )
                found.append((float(A), self.stable(A, sigma)))
        return sorted(found)

    def stable(self, A: float, sigma: float) -> bool:
        """Whether the steady state (A, sigma) is stable; not where the Jacobian is not finite
        (at an end of S+ where kappa of (39) folds, rho's slope is infinite), as the engine's
        branches count it."""
        psi = float(self.flow.steady_phase(A, sigma=sigma))
        J = self.flow.jac(A, psi, sigma=sigma)
        return bool(np.isfinite(J).all() and np.all(np.linalg.eigvals(J).real < 0))


def response_curve(params: Params, model: str = "slowflow") -> ResponseCurve:
    """The response curve of (46) for ``params`` (its sigma is not used) with the slow flow
    ``model`` ("slowflow" or "corrected")."""
    flow = SlowFlow(params, model)
    top = 10.0 * (params.Abar / params.gamma + 1.0) if params.gamma > 0 else 1e3  # E >= gamma pi^2 A^2
    top = min(top, flow.A_max * (1 - _EDGE)) if np.isfinite(flow.A_max) else top
    A = np.geomspace(flow.A_min * (1 + _EDGE), top, GRID)
    A = np.sort(np.concatenate([A, _turns(flow, A)]))
    low, high = sigma_on_curve(flow, A, rounding=_TURN)
    return ResponseCurve(flow, A, low, high)


def impact_free(params: Params) -> tuple:
    """(A, |w| amplitude) of the impact-free 2pi-response of (8) at ``params``: the linear flight
    forced by F cos(tau), X = |Y_X| sin(tau + phase). A steady state of the system where the
    particle's amplitude is below 1 (it then never reaches the walls)."""
    Y = _impact_free_amplitudes(params)
    return float(abs(Y[0])), float(abs(Y[2]))


def impact_free_state(params: Params) -> np.ndarray:
    """The impact-free response's state [X, X', w, w'] at tau = 0 (Re Y)."""
    return _impact_free_amplitudes(params).real


def _impact_free_amplitudes(params: Params) -> np.ndarray:
    model = ImpactModel(params)
    return np.linalg.solve(1j * np.eye(4) - model.matrix, model.forcing.astype(complex))


def _discriminant(flow: SlowFlow, A):
    """(pi^2 A Abar)^2 - E^2 of (46): steady states of amplitude A exist where it is >= 0."""
    E, _ = flow.steady_balances(A, sigma=0.0)
    return (np.pi**2 * A * flow.params.Abar) ** 2 - E**2


def _turns(flow: SlowFlow, A) -> np.ndarray:
    """The amplitudes where the response curve turns between grid points (its two roots of (46)
    meet: the peak of a resonance, the ends of a closed curve), by Brent on the discriminant, so
    that a point near a peak is bracketed on one of the two roots."""
    disc = _discriminant(flow, A)
    found = []
    for i in np.flatnonzero(np.sign(disc[:-1]) * np.sign(disc[1:]) < 0):
        found.append(
            optimize.brentq(
                lambda a: float(_discriminant(flow, a)),
                A[i],
                A[i + 1],
                xtol=1e-15,
                rtol=4 * np.finfo(float).eps,
            )
        )
    return np.array(found)
