"""Curves of Neimark-Sacker (NS) points of periodic orbits of (9) in two parameters: the
complex minimally augmented system.

The monodromy matrix has the pair exp(+-i theta) exactly when the block-cyclic matrix J_theta of
multiple shooting with the closing block -exp(i theta) I is singular. With complex bordering
vectors b, c the scalar g in

    [[J_theta, b], [c^H, 0]] [v; g] = [0; 1]

is complex; Re g = Im g = 0 are two real equations, and theta joins the unknowns, so the system
is (x, p2, theta) of size 4m + 2, continued in p1. dg/dz = -w^H d(J v)/dz with w from the adjoint
system; d(J v)/dz comes from F_z at x + h Re v and x + h Im v (two extra integrations), and
dg/dtheta = i exp(i theta) w_last^H v_0 in closed form. On the curve, the strong resonances
1:1 (R1, theta = 0), 1:2 (R2, theta = pi), 1:3 (R3, theta = 2 pi/3) and 1:4 (R4, theta = pi/2),
fold-NS (LPNS, a further multiplier +1) and flip-NS (PDNS, -1) are located by test functions.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.orbits.codim2.minaug import MultiplierCurveProblem
from slosh_bif.orbits.floquet import floquet_multipliers

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

    def _matrix_at(self, x, p):
        arcs = self.shooting.arcs(x[:-2], self.params_at(x, p))
        return arcs, self.shooting.jacobian_of(arcs, np.exp(1j * x[-1]))

    def _second_uncached(self, x, p):
        arcs, v, w, _ = self._solve(x, p)
        y, P = x[:-2], self.params_at(x, p)
        h = 1e-5 * (1 + np.linalg.norm(y)) / np.linalg.norm(v)
        base_J, base_S = self.shooting.jacobian_of(arcs), arcs.sens.reshape(len(y), -1)
        parts = []
        for direction in (v.real, v.imag):
            shifted = self.shooting.arcs(y + h * direction, P)
            parts.append(((self.shooting.jacobian_of(shifted) - base_J) / h, (shifted.sens.reshape(len(y), -1) - base_S) / h))
        dJ = parts[0][0] + 1j * parts[1][0]  # d(J v)/dx as a matrix acting on the direction
        dS = parts[0][1] + 1j * parts[1][1]
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

    def jacobian(self, x, p):
        arcs = self._solve(x, p)[0]
        g_x, _, g_p2, g_theta = self._second(x, p)
        n = len(x) - 2
        top = np.column_stack([self.shooting.jacobian_of(arcs), arcs.sens.reshape(n, -1)[:, self._columns[1]], np.zeros(n)])
        g_row = np.concatenate([g_x, [g_p2, g_theta]])
        return np.vstack([top, g_row.real, g_row.imag])

    def dparam(self, x, p):
        arcs = self._solve(x, p)[0]
        _, g_p1, _, _ = self._second(x, p)
        return np.concatenate([arcs.sens.reshape(len(x) - 2, -1)[:, self._columns[0]], [g_p1.real, g_p1.imag]])

    def eigenvalues(self, x, p):
        """The multipliers, the critical pair (nearest exp(+-i theta)) first."""
        arcs = self._solve(x, p)[0]
        if not np.all(np.isfinite(arcs.monodromy)):
            return np.full(4, np.nan + 0j)
        mu = floquet_multipliers(arcs.mats)
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
