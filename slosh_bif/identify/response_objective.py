"""The residuals of a frequency-response fit as a function of its free parameters: each measured
point (sigma_i, A_i) against the response of the chosen model that it is compared with (the
steady states of the slow flows (46), or the stable 2pi-orbits of (9) and (8) followed from one
parameter set to the next), divided by the point's std, within the parameters' admissible ranges
(eq. 21's kappa real)."""

from __future__ import annotations

import warnings

import numpy as np

from slosh_bif.identify.assignment import pick
from slosh_bif.identify.response_data import ResponseData
from slosh_bif.identify.response_impact import ImpactResponse
from slosh_bif.identify.response_model import impact_free, response_curve
from slosh_bif.identify.response_orbits import OrbitResponse
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import dissipation_at_unit_speed
from slosh_bif.slowflow.flow import AsymptoticsWarning

__all__ = [
    "Objective",
    "residuals",
    "model_amplitudes",
    "steady_states",
    "orbit_response",
    "admissible_ranges",
]


def residuals(data: ResponseData, params: Params, model: str = "slowflow") -> np.ndarray:
    """(A_i - A_model_i) / std_i, A_model_i the steady state of the slow flow ``model`` point i is
    on (:func:`model_amplitudes`)."""
    out = data.A - model_amplitudes(data, params, model)
    return out / data.std if data.std is not None else out


def model_amplitudes(data: ResponseData, params: Params, model: str = "slowflow") -> np.ndarray:
    """The amplitude of the steady state each point is compared with: the candidates at its sigma
    are the steady states of (46) and the impact-free response where the particle stays inside the
    walls (:func:`~.response_model.impact_free`), and the point takes the stable one that explains
    it best, its sweep's continuing one where that explains it nearly as well
    (:func:`~.assignment.pick`). Any steady state where none is stable; 0 where there is none."""
    states = steady_states(data, params, model)
    out = np.empty(len(data))
    for i, previous in data.sweep_order():
        candidates = states[i] or [(0.0, True)]
        k = pick(data, i, None if previous is None else out[previous], candidates)
        out[i] = candidates[k][0]
    return out


def steady_states(data: ResponseData, params: Params, model: str = "slowflow") -> list:
    """(A, stable) of every steady state of the slow flow ``model`` at each point's sigma, the
    impact-free response among them where it stays inside the walls."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        # data in Hz: each point's own gamma and Abar, so its own curve
        shared = response_curve(params, model) if data.ratio is None else None
        return [_states(data, params, model, i, shared) for i in range(len(data))]


def _states(data: ResponseData, params: Params, model: str, i: int, shared) -> list:
    """(A, stable) of every steady state at point i's sigma (on the ``shared`` curve, or its own),
    the impact-free response among them where it stays inside the walls."""
    at = data.params_at(params, i)
    states = (shared or response_curve(at, model)).states_at(float(data.sigma[i]))
    A, w = impact_free(at)
    return states + [(A, True)] if w < 1.0 else states


class Objective:
    """Residuals as a function of the continuous free parameters, each within its admissible range
    (``lower``, ``upper``): gamma >= 0, Abar > 0, eps > 0 with 1 - eps sigma > 0 at every point,
    and lam >= 0 and chi > 0 where kappa (21) stays real (C, the energy fraction lost at unit
    speed, is linear in lam and goes as chi**-a). An elastic wall, lam -> 0, is a bound the fit
    may reach, not a point at infinity."""

    def __init__(self, data, base: Params, names, model, progress=None, family=None):
        self.data, self.base, self.names, self.model = data, base, tuple(names), model
        # the full model's orbits are found once, at the base set, and followed from there (from
        # a ``family`` of (9)'s orbits already traced, when given)
        self.orbits = orbit_response(data, base, model, progress, family)
        # an orbit's A1 is Newton's, to ~1e-12: differences of scipy's default step (1.5e-8 relative)
        # would be noise for a parameter the response hardly feels (eps)
        self.diff_step = None if self.orbits is None else 1e-6
        # (9)'s orbits carry their own parameter derivatives (the variational equations), (8)'s
        # theirs (the saltation sensitivities along each orbit, but in the measured wall's
        # parameters); the slow flows' states are differenced
        own = isinstance(self.orbits, OrbitResponse) or (
            isinstance(self.orbits, ImpactResponse) and self.orbits.differentiates(self.names)
        )
        self.jacobian = self._jacobian if own else None
        self._at = None  # the z the orbits were last moved to (None: the last call lost them)
        self.lost = False  # whether the last call lost the orbits (or left the admissible set)
        ranges = admissible_ranges(base, float(np.max(data.sigma)))
        self.lower = np.array([ranges[n][0] for n in self.names])
        self.upper = np.array([ranges[n][1] for n in self.names])

    def params(self, z) -> Params:
        return self.base.replace(**{n: float(v) for n, v in zip(self.names, z)})

    def save(self):
        """The orbits' state (each evaluation moves them on), for :meth:`restore`; None for the slow flows."""
        return None if self.orbits is None else self.orbits.state()

    def restore(self, state) -> None:
        if self.orbits is not None:
            self.orbits.restore(state)

    def __call__(self, z):
        self._at, self.lost = None, False
        try:
            if self.orbits is None:
                return residuals(self.data, self.params(z), self.model)
            r = self.data.A - self.orbits.amplitudes(self.params(z))
            self._at = np.array(z, dtype=float)
            return r / self.data.std if self.data.std is not None else r
        except ValueError:  # outside the admissible set, or an orbit of (9) lost: far off
            self.lost = self.orbits is not None
            return np.full(len(self.data), 1e3 * (1.0 + float(np.abs(self.data.A).max())))

    def _jacobian(self, z):
        """d residuals / dz from (9)'s orbits at z (moved there first unless the last call was at
        z); zero where the orbits are lost (the residual is then a constant)."""
        if self._at is None or not np.array_equal(self._at, z):
            self(z)
        if self._at is None:
            return np.zeros((len(self.data), len(self.names)))
        J = -self.orbits.gradient(self.names)
        return J / self.data.std[:, None] if self.data.std is not None else J


def admissible_ranges(base: Params, sigma_top: float) -> dict:
    """(lower, upper) of each continuous parameter about ``base``: kappa (21) real (C, the energy
    fraction lost at unit speed, is linear in lam and goes as chi**-a), gamma >= 0, Abar > 0, and
    eps > 0 with the vessel's stiffness 1 - eps sigma positive up to ``sigma_top``."""
    C = float(dissipation_at_unit_speed(base.lam, base.chi, base.n, base.pbar))
    a = base.pbar / (2 * (base.n + 1)) + 0.5
    return {
        "lam": (1e-9, base.lam / C * (1 - 1e-9) if C > 0 else np.inf),
        "chi": (base.chi * C ** (1 / a) * (1 + 1e-9) if C > 0 else 1e-9, np.inf),
        "gamma": (0.0, np.inf),
        "Abar": (1e-9, np.inf),
        "eps": (1e-9, 1 / sigma_top * (1 - 1e-9) if sigma_top > 0 else np.inf),
    }


def orbit_response(data, base: Params, model: str, progress, family=None):
    """The orbits each point follows, found at ``base``, for the orbit models; None for the slow flows."""
    if model == "smooth":
        return OrbitResponse(data, base, progress, family=family)
    if model in ("impact", "impact-corrected"):
        variant = "corrected" if model == "impact-corrected" else "paper"
        return ImpactResponse(data, base, progress, variant=variant)
    return None
