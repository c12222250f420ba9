"""The restitution law on the stable manifold branch S+: kappa(A) and rho(A) of (39), (40), and
where S+ ends.

On S+ the impact speed (38) depends on the amplitude A through alpha(A, rho), so for a
velocity-dependent wall (pbar != 0) kappa, and with it rho (31) and the manifold (36), depend on
A through the implicit eq. (39), G(kappa, A) = kappa^2 - 1 + delta(v(kappa, A)) = 0. For pbar = 0
kappa is the Newtonian constant of (40). This one object answers, once per parameter set, what
the slow flow, the critical forcing, the regime classifier and the slow-flow start of shooting
all ask: rho(A) and d rho/dA, alpha_S+(A), and the window [A_min, A_max] of A where S+ exists.

Notes
-----
S+ carries the root of (39) reached continuously from the elastic limit (the largest root in
(0, 1]). It can end, as A decreases or increases, in three ways, each located to machine
precision from its own equations:

* ``manifold end (36)``: A = A_min(rho(kappa)), where S+ meets the unstable branch of (36) (the
  only end for pbar = 0, and the lower end for small dissipation);
* ``fold of (39)``: G = dG/dkappa = 0, the root merges with a smaller one and vanishes (Newton
  on the pair, with the generated gradient);
* ``kappa reaches 0``: G(0, A) = 0, the wall becomes perfectly plastic (bracketing in A).

For pbar > 0 the impact speed grows with A and the dissipation with it, so S+ also ends at a
finite largest amplitude; for pbar < 0 the dissipation grows as the speed falls, so the lower
end may be a fold of (39) above A_min(rho).
"""

from __future__ import annotations

import math

import numpy as np

from slosh_bif.model import manifold
from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.restitution import eq21 as restitution
from slosh_bif.model.restitution.checks import check_params
from slosh_bif.model.restitution.eq39 import (
    END_KINDS,
    SCAN,
    ManifoldEnd,
    eq39_for,
    scipy_optimize,
)

__all__ = ["ManifoldLaw", "END_KINDS"]

BATCH = 8  # from this many amplitudes on, kappa is solved for all of them in one vectorised pass


class ManifoldLaw:
    """kappa(A), rho(A), alpha_S+(A) on S+ and the ends of S+, for one parameter set.

    Attributes
    ----------
    newtonian : bool
        pbar == 0: kappa (40) and rho do not depend on A.
    lower, upper : ManifoldEnd or None
        The ends of S+ (``upper`` is None when S+ extends to every large amplitude).
    A_min, A_max : float
        The window of S+: ``lower.A`` and ``upper.A`` (``inf`` without an upper end).
    kappa_at_end : float
        kappa of (39) at the lower end.
    prefix : str
        Of the generated functions this law's slow flow uses (the paper's: none); ``values``,
        ``slopes`` and ``end_values`` give their arguments after A (the corrected law has the same).
    """

    prefix = ""

    def __init__(self, params):
        check_params(params)
        P = self.params = params
        self.newtonian = P.pbar == 0
        self._delta1 = float(restitution.dissipation_at_unit_speed(P.lam, P.chi, P.n, P.pbar))
        self._expo = P.pbar / (P.n + 1)
        if self.newtonian or self._delta1 == 0.0:
            k = float(restitution.kappa_newtonian(P.lam, P.chi, P.n)) if self.newtonian else 1.0
            self._rho0 = float(restitution.rho(k))
            self.lower, self.upper = ManifoldEnd(float(gen.sim_a_min(self._rho0)), k, END_KINDS[0]), None
        else:
            self._rho0 = None
            self._eq = eq39_for(P.lam, P.chi, P.n, P.pbar)
            self.lower, self.upper = self._eq.lower, self._eq.upper
        self.A_min = self.lower.A
        self.A_max = self.upper.A if self.upper is not None else math.inf
        self.kappa_at_end = self.lower.kappa

    def kappa(self, A):
        """kappa of (39) on S+ at amplitude(s) A inside the window (NaN outside)."""
        A = np.asarray(A, dtype=float)
        if self._rho0 is not None:
            return np.full_like(A, self.lower.kappa)
        out = np.full(A.shape, np.nan)
        fold = [e for e in (self.lower, self.upper) if e is not None and e.kind == END_KINDS[1]]
        batch = None
        if A.size >= BATCH:  # the scan of every amplitude at once; brentq's for a few
            inside = (A >= self.A_min) & (A <= self.A_max)
            batch = np.full(A.shape, np.nan)
            batch[inside] = restitution.largest_roots(A[inside], self._delta1, self._expo, xtol=1e-15)
        for i, a in np.ndenumerate(A):
            if not self.A_min <= a <= self.A_max:
                continue
            at_end = [
                e
                for e in (self.lower, self.upper)
                if e is not None and abs(a - e.A) <= 4 * np.finfo(float).eps * e.A
            ]
            if at_end:  # exactly on an end, where the root sits on the edge of its bracket
                out[i] = at_end[0].kappa
                continue
            k = self._eq._largest_root(a) if batch is None else batch[i]
            if not np.isfinite(k) and self.lower.kind == END_KINDS[0]:
                k = self._eq._root_near_manifold_end(a, self.lower.kappa)
            near_fold = [e for e in fold if not np.isfinite(k) or abs(k - e.kappa) < 0.2]
            if near_fold and self._eq._G(near_fold[0].kappa, a) < 0:
                # Two roots close to the fold fall in one cell of the scan: bracket the upper one.
                k = scipy_optimize().brentq(
                    lambda kk: self._eq._G(kk, a), near_fold[0].kappa, 1.0, xtol=1e-15
                )
            out[i] = k
        return out

    # -- what the slow flow asks ----------------------------------------------------------------

    def rho(self, A):
        """rho on S+ at amplitude(s) A, and d rho/dA (zero for pbar = 0)."""
        A = np.asarray(A, dtype=float)
        if self._rho0 is not None:
            return np.full_like(A, self._rho0), np.zeros_like(A)
        k = self.kappa(A)
        if np.any(~np.isfinite(k)):
            bad = A[~np.isfinite(k)]
            raise ValueError(
                f"amplitude A = {bad.ravel()[:3]} lies outside S+, A in [{self.A_min:.10g}, "
                f"{self.A_max:.10g}]: {self.describe()}"
            )
        with np.errstate(divide="ignore", invalid="ignore"):
            g_kappa, g_A = gen.manifold_kappa_residual_grad(k, A, self._delta1, self._expo)
            return restitution.rho(k), restitution.drho_dkappa(k) * (-g_A / g_kappa)

    def alpha(self, A):
        """alpha_S+(A) with rho(A), eq. (36)."""
        return manifold.alpha(A, self.rho(A)[0])

    def values(self, A):
        """(rho,) at A: the arguments of the generated slow-flow functions after A (and psi)."""
        return (self.rho(A)[0],)

    def slopes(self, A):
        """(rho, d rho/dA): the arguments of ``slow_jac`` and ``steady_residual_grad``."""
        return self.rho(A)

    def end_values(self, end: ManifoldEnd):
        """(rho,) at an end of S+ (its kappa is part of the end, and may be 0: a plastic wall)."""
        return (float(restitution.rho_unchecked(end.kappa)),)

    def describe(self) -> str:
        """The window of S+ and what ends it, in one line."""
        upper = (
            self.upper.describe()
            if self.upper is not None
            else f"no upper end (A up to {SCAN[-1]:g} checked)"
            if self._rho0 is None
            else "no upper end"
        )
        return f"{self.lower.describe()}; {upper}"

    def branches(self, A_max: float, points: int = 300):
        """(A, alpha_S+, alpha_unstable) of (36) with rho(A), for A from A_min to ``A_max`` (at
        most the window's upper end), clustered at the fold where alpha has a square-root
        singularity."""
        top = min(A_max, self.A_max)
        A = self.A_min + (top - self.A_min) * np.linspace(0.0, 1.0, points) ** 2
        rho = self.rho(A)[0]
        return A, manifold.alpha(A, rho, manifold.STABLE), manifold.alpha(A, rho, manifold.UNSTABLE)
