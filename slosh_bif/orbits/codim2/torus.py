"""Curves of Neimark-Sacker (NS) points of periodic orbits of (9) in two parameters, on a
real minimally augmented system parametrised by kappa = cos(theta), as MatCont's are.

The monodromy matrix M has the pair exp(+-i theta) exactly when M^2 - 2 kappa M + I is singular
with a two-dimensional null space. In multiple shooting the same condition is a real block matrix
of two chains of arcs: with J_0 the block-cyclic matrix of the arcs Phi_k with the closing block
left empty,

    A(kappa) = [[J_0 - 2 kappa E, E], [-E, J_0]],      E: I in the block that closes the period,

is singular exactly there (its null vectors are chains (u, v) with M v = u and
M u - 2 kappa u + v = 0). With two bordering columns, [[A, B], [C^T, 0]] [V; G] = [0; I] gives a
2 x 2 matrix G that vanishes on the curve; its first column, two real equations, joins the
shooting residual, and kappa the unknowns (x, p2, kappa), continued in p1. For |kappa| < 1 the
first column vanishes only where the whole of G does (a real multiplier mu solves
mu + 1/mu = 2 kappa only for |kappa| >= 1). dG = -W^T dA V with W from the transposed system;
dA along a direction needs the arcs' second derivatives along the two chains of V's first
column (two replays of the second-order variational equations on the arcs' steps, as on the
fold curves), and
dG/dkappa = 2 W_u,last^T V_u,first in closed form.

Unlike theta, kappa is a regular coordinate through the strong resonances 1:1 (R1, kappa = 1) and
1:2 (R2, kappa = -1), where the pair meets on the real axis: both are zeros of test functions,
located on the curve, and the curve ends there (beyond them the same system traces a neutral
saddle, real multipliers mu and 1/mu, which is no bifurcation). Also located: 1:3 (R3,
kappa = -1/2), 1:4 (R4, kappa = 0), fold-NS (LPNS, a further multiplier +1) and flip-NS (PDNS, -1).
"""

from __future__ import annotations

import numpy as np

from slosh_bif.orbits.codim2.minaug import MinAugCurveProblem

__all__ = ["TorusCurveProblem"]

RESONANCES = {"R1": 1.0, "R2": -1.0, "R3": -0.5, "R4": 0.0}
NAMES = {
    "R1": "1:1 resonance",
    "R2": "1:2 resonance",
    "R3": "1:3 resonance",
    "R4": "1:4 resonance",
    "LPNS": "fold-Neimark-Sacker",
    "PDNS": "flip-Neimark-Sacker",
}


class TorusCurveProblem(MinAugCurveProblem):
    """Points (x, p2, kappa) of (9) at p1 where the orbit has multipliers exp(+-i theta), kappa =
    cos(theta)."""

    kind = "NS"
    test_kinds = ("R1", "R2", "R3", "R4", "LPNS", "PDNS")
    terminal_kinds = ("R1", "R2")

    def __init__(self, params, p1: str = "sigma", p2: str = "Abar", **options):
        super().__init__(params, p1, p2, **options)
        self.names = self.orbits.names + (p2, "kappa")

    _extra = 2  # p2 and kappa follow the orbit's states
    _borders = 2  # the real pair's two-dimensional null space

    # Room beyond the resonances, so that kappa -+ 1 change sign there and R1/R2 are located.
    KAPPA_MAX = 1.5

    def in_domain(self, x, p) -> bool:
        return abs(x[-1]) <= self.KAPPA_MAX and super().in_domain(x, p)

    def _matrix_at(self, x, p):
        arcs = self.orbits.arcs(x[:-2], self.params_at(x, p))
        J0 = self.orbits.jacobian_of(arcs, 0.0)
        n = len(J0)
        A = np.zeros((2 * n, 2 * n))
        A[:n, :n] = A[n:, n:] = J0
        last, first = slice(n - 4, n), slice(0, 4)
        A[last, first] -= 2 * x[-1] * np.eye(4)
        A[last, n : n + 4] += np.eye(4)
        A[n + n - 4 :, first] -= np.eye(4)
        return arcs, A

    def _solve(self, x, p):
        """(arcs, V's first column, W, G's first column)."""
        arcs, V, W, G = self._bordered(x, p)
        return arcs, V[:, 0], W, G[:, 0]

    def _second_uncached(self, x, p):
        _, v, W, _ = self._solve(x, p)
        y, P = x[:-2], self.params_at(x, p)
        n = len(y)
        (dJ_u, dS_u), (dJ_v, dS_v) = (self._along(y, P, d) for d in (v[:n], v[n:]))
        Wu, Wv = W[:n], W[n:]
        g_x = -(dJ_u.T @ Wu + dJ_v.T @ Wv).T  # rows: the two entries of G's first column
        g_p1 = -(dS_u[:, self._columns[0]] @ Wu + dS_v[:, self._columns[0]] @ Wv)
        g_p2 = -(dS_u[:, self._columns[1]] @ Wu + dS_v[:, self._columns[1]] @ Wv)
        g_kappa = 2 * (W[n - 4 : n].T @ v[:4])
        return g_x, g_p1, g_p2, g_kappa

    def residual(self, x, p):
        arcs, _, _, g = self._solve(x, p)
        return np.concatenate([self.orbits.residual_of(x[:-2], arcs), g])

    def _g_row(self, second):
        g_x, g_p1, g_p2, g_kappa = second
        return np.column_stack([g_x, g_p2, g_kappa, g_p1])

    def eigenvalues(self, x, p):
        """The multipliers, the critical pair (nearest exp(+-i theta)) first."""
        mu = self.multipliers(x, p)
        target = np.exp(1j * np.arccos(np.clip(x[-1], -1.0, 1.0)))
        distance = np.minimum(np.abs(mu - target), np.abs(mu - target.conjugate()))
        return mu[np.argsort(distance)]

    @staticmethod
    def is_stable(multipliers) -> bool:
        return bool(np.all(np.abs(multipliers[2:]) < 1))

    def test_functions(self, x, p):
        kappa = x[-1]
        others = self.eigenvalues(x, p)[2:]
        return (
            *(kappa - RESONANCES[k] for k in ("R1", "R2", "R3", "R4")),
            np.prod(others - 1).real,
            np.prod(others + 1).real,
        )

    def confirm(self, kind, x, p):
        kappa = x[-1]
        if kind in ("R1", "R2"):
            pair = self.eigenvalues(x, p)[:2]
            return (
                f"{NAMES[kind]}: kappa = {kappa:.6f}, the pair of multipliers at {pair[0].real:.6f}, "
                f"{pair[1].real:.6f}; the NS curve ends here"
            )
        return f"{NAMES[kind]}: kappa = {kappa:.6f} (theta = {np.arccos(np.clip(kappa, -1, 1)):.6f})"
