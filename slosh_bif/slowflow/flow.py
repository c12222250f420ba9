"""The slow flow on the stable manifold branch S+: eqs. (36), (39), (43), (45), (46).

In slow time T1 = eps * tau, on S+ (alpha = alpha_S+(A, rho)):

    D1 A   = -gamma A / 2 - 4 rho alpha^2 (1 - beta^2) / (pi^2 A) + (Abar / 2) cos psi          (45a)
    D1 psi = -(sigma - (1 - beta^2)) / 2 + 4 alpha (1 - alpha)(1 - beta^2) / (pi^2 A^2) - Abar sin psi / (2 A)

The free flow (43) is the case Abar = 0, sigma = 0. Steady states satisfy (46),

    pi^4 A^2 Abar^2 = (gamma pi^2 A^2 + 8 rho alpha^2 (1 - beta^2))^2
                      + (pi^2 (sigma - (1 - beta^2)) A^2 - 8 alpha (1 - alpha)(1 - beta^2))^2.

For pbar = 0 rho is a constant (eq. 40); otherwise kappa, hence rho, depends on A through the
implicit eq. (39) and the derivatives carry d rho/dA (implicit differentiation).

Notes
-----
Derived by ``derivations/slow_flow.py`` (see ``derivations/REPORT.md``). Two printed equations do
not survive the derivation, and numerics on the full models settle both:

* (43) has an extra factor rho in the impact term of D1 A (``4 rho alpha^2 (1 - beta^2) rho``);
  the free decay of the vibro-impact model (8) at the Fig. 9 parameters follows the derived form.
* (46) prints ``gamma pi^2 A^2 - 8 rho alpha^2 (1 - beta^2)`` in its first bracket; squaring the
  steady state of (45) gives ``+``: the impacts dissipate, they do not feed, the vessel. The smooth
  model (9) confirms it (Fig. 10 set with Abar = 0.5: the printed sign predicts stable-branch
  states up to A = 4.25 at sigma = 0 which (9) does not have).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from slosh_bif.model import restitution
from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import check_model, manifold_law

__all__ = ["AsymptoticsWarning", "SlowFlow", "SlowTrajectory", "asymptotics_concerns", "triangle_wave"]


class AsymptoticsWarning(UserWarning):
    """The slow flow is used where the asymptotics behind it are known, or expected, to be poor."""


# Where the multiple-scales model was compared with the full model (docs/findings/regimes.md, "What the full
# model
# says"): eps = 0.05-0.1, beta = 0-0.3, and eq. (21) is accurate only for small dissipation.
ASYMPTOTICS_LIMITS = {"eps": 0.1, "beta": 0.5, "wall_dissipation": 0.5, "corrected_n": 10}


def asymptotics_concerns(params: Params, model: str = "slowflow") -> list:
    """Why the slow flow (``model``) may be inaccurate for ``params`` (empty when no known reason).
    The corrected model takes kappa from the wall itself, so the concern about (21) is not its."""
    P = params
    concerns = []
    if P.eps > ASYMPTOTICS_LIMITS["eps"]:
        concerns.append(f"eps = {P.eps:g} > {ASYMPTOTICS_LIMITS['eps']:g}: the expansion is in powers of eps")
    if P.beta > ASYMPTOTICS_LIMITS["beta"]:
        concerns.append(
            f"beta = {P.beta:g} > {ASYMPTOTICS_LIMITS['beta']:g}: the triangle wave solves (24b) "
            "only at beta = 0, "
            "and near beta = 1 the particle's own frequency meets the 1:1 resonance"
        )
    if check_model(model) == "corrected" and P.n < ASYMPTOTICS_LIMITS["corrected_n"]:
        concerns.append(
            f"n = {P.n} < {ASYMPTOTICS_LIMITS['corrected_n']}: the contact lasts a large part of "
            "the period and the vessel moves the particle during it, "
            "which the corrected model (an instantaneous impact at the wall's kappa and clearance) "
            "leaves out (n = 6: 1-8 % from (9) at the Fig. 10 set's forcing, 20 % and more at the "
            "Fig. 13 set's)"
        )
    delta = float(restitution.dissipation_at_unit_speed(P.lam, P.chi, P.n, P.pbar))
    if delta > ASYMPTOTICS_LIMITS["wall_dissipation"] and check_model(model) == "slowflow":
        concerns.append(
            f"the wall loses {100 * delta:.0f} % of the energy per impact (kappa = "
            f"{np.sqrt(1 - delta):.2f} at unit speed): "
            "eq. (21) is first order in the dissipation and under-estimates kappa there (n = 6, "
            "Figs. 11-12: 0.27 vs 0.63)"
        )
    return concerns


def triangle_wave(T0, alpha, eta):
    """(f, df/dT0) of the impacting particle's motion relative to the vessel in the multiple-scales
    ansatz, f(T0) = (2 alpha / pi) arcsin(cos(T0 - eta)) (29, 35; the paper's Fig. 5): a triangle
    wave of amplitude alpha, turning at the impacts T0 = eta (mod pi)."""
    T0 = np.asarray(T0, dtype=float)
    return 2 * alpha / np.pi * np.arcsin(np.cos(T0 - eta)), -2 * alpha / np.pi * np.sign(np.sin(T0 - eta))


class SlowFlow:
    """The slow flow (45) and steady states (46) on S+ for one parameter set.

    ``model``: ``"slowflow"`` (the paper's: kappa of (21)/(39), the wall at |w| = 1) or
    ``"corrected"`` (kappa and the clearance D of the measured wall,
    :mod:`slosh_bif.model.restitution.corrected`); every method below is the same for both.
    """

    def __init__(self, params: Params, model: str = "slowflow"):
        if not isinstance(params, Params):
            raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
        self.params = params
        self.model = check_model(model)
        concerns = asymptotics_concerns(params, model)
        if concerns:
            warnings.warn(
                "slow flow outside its checked range: " + "; ".join(concerns),
                AsymptoticsWarning,
                stacklevel=2,
            )
        P = params
        self._slow = (P.beta, P.gamma, P.sigma, P.Abar)
        self.law = manifold_law(params, model)
        self.newtonian = self.law.newtonian
        self.A_min, self.A_max, self.kappa_at_end = self.law.A_min, self.law.A_max, self.law.kappa_at_end

    # -- restitution on the manifold: asked of the law once, here for the flow's users --------

    def rho(self, A):
        """rho on S+ at amplitude(s) A, and d rho/dA (zero for pbar = 0): :meth:`ManifoldLaw.rho`."""
        return self.law.rho(A)

    def alpha(self, A):
        """alpha_S+(A) with rho(A), eq. (36)."""
        return self.law.alpha(A)

    def clearance(self, A):
        """The wall's position D on S+ at amplitude(s) A (1 for the paper's model)."""
        return (
            self.law.values(A)[1] if self.model == "corrected" else np.ones_like(np.asarray(A, dtype=float))
        )

    def generated(self, name: str):
        """The generated function ``name`` of this flow's model (its arguments after A and psi:
        ``law.values(A)``, or ``law.slopes(A)`` for Jacobians and gradients)."""
        return getattr(gen, self.law.prefix + name)

    # -- the flow and its steady states ---------------------------------------------------------

    def _check_on_manifold(self, A):
        A = np.asarray(A, dtype=float)
        if np.any(~np.isfinite(A)) or np.any(A < self.A_min) or np.any(A > self.A_max):
            raise ValueError(
                f"amplitude A must be finite and in [A_min, A_max] = [{self.A_min:.10g}, "
                f"{self.A_max:.10g}] (S+: {self.law.describe()}); got {A}"
            )
        return A

    def rhs(self, A, psi, sigma=None, Abar=None):
        """[D1 A, D1 psi] of (45), shape ``(2,) + broadcast(A, psi).shape``.

        ``sigma`` and ``Abar`` override the parameter set's values (this and the methods below).
        """
        A = self._check_on_manifold(A)
        return self.generated("slow_rhs")(A, psi, *self.law.values(A), *self._slow_with(sigma, Abar))

    def jac(self, A, psi, sigma=None, Abar=None):
        """Jacobian of (45) in (A, psi), shape ``(2, 2) + ...``; its eigenvalues give stability."""
        A = self._check_on_manifold(A)
        return self.generated("slow_jac")(A, psi, *self.law.slopes(A), *self._slow_with(sigma, Abar))

    def dparams(self, A, psi, sigma=None, Abar=None):
        """d(45)/d(sigma, Abar), shape ``(2, 2) + ...`` (columns sigma, Abar)."""
        A = self._check_on_manifold(A)
        return self.generated("slow_dparams")(A, psi, *self.law.values(A), *self._slow_with(sigma, Abar))

    def steady_residual(self, A, sigma=None, Abar=None):
        """Residual of (46) at amplitude(s) A (optionally at other sigma, Abar)."""
        A = self._check_on_manifold(A)
        return self.generated("steady_residual")(A, *self.law.values(A), *self._slow_with(sigma, Abar))

    def steady_residual_grad(self, A, sigma=None, Abar=None):
        """[dR/dA, dR/dsigma, dR/dAbar] of (46)."""
        A = self._check_on_manifold(A)
        return self.generated("steady_residual_grad")(A, *self.law.slopes(A), *self._slow_with(sigma, Abar))

    def steady_balances(self, A, sigma=None, Abar=None):
        """(E, Phi) of (46) at amplitude A: at a steady state pi^2 A Abar (cos psi, sin psi) = (E, Phi).

        E (the energy balance) does not depend on sigma or Abar; Phi is linear in sigma.
        """
        A = self._check_on_manifold(A)
        # at an end of S+ located by its own equations (pbar != 0), alpha's root may be a few ulps
        # below zero: NaN there, read as no steady state, not a warning to the user
        with np.errstate(invalid="ignore"):
            return self.generated("steady_balances")(A, *self.law.values(A), *self._slow_with(sigma, Abar))

    def steady_phase(self, A, sigma=None, Abar=None):
        """psi of the steady state of amplitude A (requires Abar > 0)."""
        energy, phase = self.steady_balances(A, sigma, Abar)
        return np.arctan2(phase, energy)

    def _slow_with(self, sigma, Abar):
        beta, gamma, s, a = self._slow
        return beta, gamma, s if sigma is None else sigma, a if Abar is None else Abar

    def fast_state(self, A, psi, tau):
        """The leading-order motion on S+ at slow state (A, psi), as states [X, X', w, w'] at the
        fast times ``tau`` (shape ``tau.shape + (4,)``): X = A sin(tau + psi) (25) and
        w = X + f with the triangle wave f = (2 alpha / pi) arcsin(cos(tau - eta)) (29, 35),
        whose impact phase eta solves (31), (32) with B = 0:
        A sin(eta + psi) = D - alpha, A cos(eta + psi) = rho alpha (the wall at D = 1 in the paper).

        A start guess for shooting on (9): X is what the slow flow predicts; w is the leading
        order only (the smooth wall of (9) bends the triangle's corners and the orbit's impacts
        lose energy, which the elastic triangle wave does not show).
        """
        A = float(self._check_on_manifold(A))
        if not np.isfinite(psi):
            raise ValueError(f"phase psi must be finite; got {psi!r}")
        tau = np.asarray(tau, dtype=float)
        alpha, rho, D = float(self.alpha(A)), float(self.rho(A)[0]), float(self.clearance(A))
        eta = np.arctan2(D - alpha, rho * alpha) - psi
        X, Xd = A * np.sin(tau + psi), A * np.cos(tau + psi)
        f, fd = triangle_wave(tau, alpha, eta)
        return np.stack([X, Xd, X + f, Xd + fd], axis=-1)

    def start_from_state(self, state):
        """(A0, psi0) on S+ for a state [X, X', w, w']: A0 = |X + i X'| (at least 1.05 A_min, just
        above the manifold's end); psi0 = 0 (the presets start at X ~ 0, where psi is ~0 anyway)."""
        return max(float(np.hypot(state[0], state[1])), 1.05 * self.A_min), 0.0

    def integrate(self, A0, psi0, T1_span, *, rtol=1e-10, atol=1e-12, t_eval=None) -> "SlowTrajectory":
        """Integrate (45) in slow time from (A0, psi0); stops at the manifold's end A = A_min."""
        self._check_on_manifold(A0)

        # The flow's square root vanishes at A_min; stay a hair above it until the event fires.
        floor = self.A_min * (1 + 1e-12) + 1e-300

        def rhs(_t, z):
            return self.rhs(max(z[0], floor), z[1])

        def reaches_end(_t, z):
            return z[0] - self.A_min

        reaches_end.terminal = True
        reaches_end.direction = -1
        from scipy.integrate import solve_ivp  # here: a process that only shoots never imports it

        sol = solve_ivp(
            rhs, T1_span, [A0, psi0], method="DOP853", rtol=rtol, atol=atol, t_eval=t_eval, events=reaches_end
        )
        if not sol.success:
            raise RuntimeError(f"slow-flow integration failed: {sol.message}")
        escaped = sol.status == 1
        T1_end = float(sol.t_events[0][0]) if escaped else float(T1_span[1])
        message = (
            f"reached the manifold's end A_min = {self.A_min:.6g} at T1 = {T1_end:.6g}: escape "
            "from 1:1 resonance"
            if escaped
            else "finished"
        )
        A = sol.y[0]
        return SlowTrajectory(
            T1=sol.t,
            A=A,
            psi=sol.y[1],
            alpha=self.alpha(np.maximum(A, self.A_min)),
            escaped=escaped,
            T1_end=T1_end,
            message=message,
        )


@dataclasses.dataclass(frozen=True)
class SlowTrajectory:
    """A solution of the slow flow: slow time T1 = eps tau, A, psi, alpha.

    ``escaped`` is True when A reached the manifold's end A_min, at slow time ``T1_end``
    (otherwise ``T1_end`` is the end of the span).
    """

    T1: np.ndarray
    A: np.ndarray
    psi: np.ndarray
    alpha: np.ndarray
    escaped: bool
    T1_end: float
    message: str
