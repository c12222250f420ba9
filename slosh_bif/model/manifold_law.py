"""The restitution law on the stable manifold branch S+: kappa(A) and rho(A) of (39), (40), and
where S+ ends.

On S+ the impact speed (38) depends on the amplitude A through alpha(A, rho), so for a
velocity-dependent wall (pbar != 0) kappa, and with it rho (31) and the manifold (36), depend on
A through the implicit eq. (39). For pbar = 0 kappa is the Newtonian constant of (40). This one
object answers, once per parameter set, what the slow flow, the critical forcing, the regime
classifier and the slow-flow start of shooting all ask: rho(A) and d rho/dA, alpha_S+(A), the
end A_min of S+ (where it meets the unstable branch, self-consistently with (39)) and kappa there.
"""

from __future__ import annotations

import numpy as np
from scipy import optimize

from slosh_bif.model import manifold, restitution
from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.params import Params

__all__ = ["ManifoldLaw"]


def _drho_dkappa(k):
    return -4.0 / (np.pi * (1.0 + k) ** 2)


class ManifoldLaw:
    """kappa(A), rho(A), alpha_S+(A) on S+ and the end of S+, for one parameter set.

    Attributes
    ----------
    newtonian : bool
        pbar == 0: kappa (40) and rho do not depend on A.
    A_min : float
        The end of S+ (its fold with the unstable branch), eq. (36) with rho(A_min).
    kappa_at_end : float
        kappa of (39) at A_min.
    """

    def __init__(self, params: Params):
        if not isinstance(params, Params):
            raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
        P = self.params = params
        self.newtonian = P.pbar == 0
        self._delta1 = float(restitution.dissipation_at_unit_speed(P.lam, P.chi, P.n, P.pbar))
        self._expo = P.pbar / (P.n + 1)
        if self.newtonian:
            self._rho0 = float(restitution.rho(restitution.kappa_newtonian(P.lam, P.chi, P.n)))
        self.A_min, self.kappa_at_end = self._end()

    def _end(self):
        """(A_min, kappa there): where S+ meets the unstable branch, self-consistently with (39)."""
        P = self.params
        if self.newtonian:
            return float(gen.sim_a_min(self._rho0)), float(restitution.kappa_newtonian(P.lam, P.chi, P.n))
        if self._delta1 == 0.0:
            return 0.0, 1.0

        def at_end(k):  # (39) with alpha = alpha_min = 1/(1 + rho^2)
            r = restitution.rho(k)
            speed = 4.0 / (np.pi * (1.0 + k) * (1.0 + r**2))
            return k**2 - 1.0 + self._delta1 * speed**self._expo

        grid = np.linspace(1.0, 1e-6, 400)
        values = [at_end(k) for k in grid]
        for i in range(len(grid) - 1):
            if np.sign(values[i]) != np.sign(values[i + 1]):
                k = optimize.brentq(at_end, grid[i + 1], grid[i], xtol=1e-15)
                return float(gen.sim_a_min(restitution.rho(k))), float(k)
        raise ValueError(f"no restitution coefficient in (0, 1) at the manifold's end for lam={P.lam}, chi={P.chi}, n={P.n}, pbar={P.pbar}")

    def rho(self, A):
        """rho on S+ at amplitude(s) A, and d rho/dA (zero for pbar = 0)."""
        A = np.asarray(A, dtype=float)
        if self.newtonian:
            return np.full_like(A, self._rho0), np.zeros_like(A)
        P = self.params
        k = restitution.kappa_on_manifold(A, P.lam, P.chi, P.n, P.pbar).kappa
        g_kappa, g_A = gen.manifold_kappa_residual_grad(k, A, self._delta1, self._expo)
        return restitution.rho(k), _drho_dkappa(k) * (-g_A / g_kappa)

    def alpha(self, A):
        """alpha_S+(A) with rho(A), eq. (36)."""
        return manifold.alpha(A, self.rho(A)[0])

    def branches(self, A_max: float, points: int = 300):
        """(A, alpha_S+, alpha_unstable) of (36) with rho(A), for A from A_min to ``A_max``
        (clustered at the fold, where alpha has a square-root singularity)."""
        A = self.A_min + (A_max - self.A_min) * np.linspace(0.0, 1.0, points) ** 2
        rho = self.rho(A)[0]
        return A, manifold.alpha(A, rho, manifold.STABLE), manifold.alpha(A, rho, manifold.UNSTABLE)
