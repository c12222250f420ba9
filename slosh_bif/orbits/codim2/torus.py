"""Curves of Neimark-Sacker (NS) points of periodic orbits of (9) in two parameters: the
complex minimally augmented system.

The monodromy matrix has the pair exp(+-i theta) exactly when the block-cyclic matrix J_theta of
multiple shooting with the closing block -exp(i theta) I is singular. With complex bordering
vectors b, c the scalar g in

    [[J_theta, b], [c^H, 0]] [v; g] = [0; 1]

is complex; Re g = Im g = 0 are two real equations, and theta joins the unknowns, so the system
is (x, p2, theta) of size 4m + 2, continued in p1. dg/dz = -w^H d(J v)/dz with w from the adjoint
system; d(J v)/dz comes from F_z at x +- h Re v and x +- h Im v (four extra integrations, central
differences as on the fold curves), and
dg/dtheta = i exp(i theta) w_last^H v_0 in closed form. On the curve, the strong resonances
1:1 (R1, theta = 0), 1:2 (R2, theta = pi), 1:3 (R3, theta = 2 pi/3) and 1:4 (R4, theta = pi/2),
fold-NS (LPNS, a further multiplier +1) and flip-NS (PDNS, -1) are located by test functions.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.orbits.codim2.minaug import MultiplierCurveProblem

__all__ = ["TorusCurveProblem"]


class TorusCurveProblem(MultiplierCurveProblem):
    """Points (x, p2, theta) of (9) at p1 where the orbit has multipliers exp(+-i theta)."""

    def __init__(self, params, p1: str = "sigma", p2: str = "Abar", **options):
        super().__init__(params, "LP", p1, p2, **options)  # LP: only for the shared set-up
        self.kind = "NS"
        self.names = self.shooting.names + (p2, "theta")
        self.branch_kind = f"NS curve of periodic orbits of (9) in ({p1}, {p2})"
        self.test_kinds = ("R1", "R2", "R3", "R4", "LPNS", "PDNS")

    _extra = 2  # p2 and theta follow the orbit's states

    def in_domain(self, x, p) -> bool:
        return 0.0 <= x[-1] <= np.pi and super().in_domain(x, p)

    edge_name = "a strong resonance, theta at 0 (1:1, R1) or pi (1:2, R2): the pair of multipliers meets on the real axis and the NS curve ends"

    def edge_distance(self, x, p) -> float:
        """How far theta is from the resonances where the curve ends. Within 1e-3 of 0 or pi the
        system's conditioning goes like theta, and the corrector stalls (seen at 2e-4) before
        theta reaches them: that stall is the end."""
        return max(0.0, min(x[-1], np.pi - x[-1]) - 1e-3)

    def _matrix_at(self, x, p):
        arcs = self.shooting.arcs(x[:-2], self.params_at(x, p))
        return arcs, self.shooting.jacobian_of(arcs, np.exp(1j * x[-1]))

    def _second_uncached(self, x, p):
        _, v, w, _ = self._solve(x, p)
        y, P = x[:-2], self.params_at(x, p)
        (dJ_re, dS_re), (dJ_im, dS_im) = (self._along(y, P, d) for d in (v.real, v.imag))
        dJ, dS = dJ_re + 1j * dJ_im, dS_re + 1j * dS_im  # d(J v)/dx as a matrix acting on the direction
        wH = w.conj()
        g_x = -(wH @ dJ)
        g_p1 = -(wH @ dS[:, self._columns[0]])
        g_p2 = -(wH @ dS[:, self._columns[1]])
        m = self.shooting.segments
        g_theta = 1j * np.exp(1j * x[-1]) * (wH[4 * (m - 1) :] @ v[:4])
        return g_x, g_p1, g_p2, g_theta

    def residual(self, x, p):
        arcs, _, _, g = self._solve(x, p)
        return np.concatenate([self.shooting.residual_of(x[:-2], arcs), [g.real, g.imag]])

    def _g_row(self, second):
        g_x, g_p1, g_p2, g_theta = second
        return np.concatenate([g_x, [g_p2, g_theta, g_p1]])

    def eigenvalues(self, x, p):
        """The multipliers, the critical pair (nearest exp(+-i theta)) first."""
        mu = self.multipliers(x, p)
        target = np.exp(1j * x[-1])
        distance = np.minimum(np.abs(mu - target), np.abs(mu - target.conjugate()))
        return mu[np.argsort(distance)]

    @staticmethod
    def is_stable(multipliers) -> bool:
        return bool(np.all(np.abs(multipliers[2:]) < 1))

    def test_functions(self, x, p):
        theta = x[-1]
        others = self.eigenvalues(x, p)[2:]
        return theta - 1e-6, theta - (np.pi - 1e-6), theta - 2 * np.pi / 3, theta - np.pi / 2, np.prod(others - 1).real, np.prod(others + 1).real

    def confirm(self, kind, x, p):
        names = {"R1": "1:1 resonance", "R2": "1:2 resonance", "R3": "1:3 resonance", "R4": "1:4 resonance", "LPNS": "fold-Neimark-Sacker", "PDNS": "flip-Neimark-Sacker"}
        return f"{names[kind]}: theta = {x[-1]:.6f}"
