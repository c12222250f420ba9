"""Curves of orbit bifurcations of (9) with a real critical multiplier, in two parameters: fold
(LP, +1), period doubling (PD, -1) and the symmetry-breaking pitchfork of symmetric orbits (BP: on
the half-period map G = -phi_pi, whose fixed points are the symmetric orbits, phi_pi's multiplier
+1, i.e. G's -1, a regular codimension-1 condition of G), each on the minimally augmented base of
:mod:`.minaug`.

Codimension-2 points located on them through test functions: on fold curves the cusp (CP: the
fold's quadratic coefficient w^T F_xx[v, v] vanishes, from the base's extra integration),
fold-flip (LPPD: a second multiplier through -1) and fold-Neimark-Sacker (LPNS); on
period-doubling curves the fold-flip (a multiplier through +1) and flip-Neimark-Sacker (PDNS); on
pitchfork curves where they meet a fold of the symmetric orbits (BPLP).
"""

from __future__ import annotations

import numpy as np

from slosh_bif.orbits.codim2.minaug import MinAugCurveProblem
from slosh_bif.orbits.orbit_tools import half_period_gap

__all__ = [
    "FoldCurveProblem",
    "FlipCurveProblem",
    "PitchforkCurveProblem",
    "repeats_early",
    "MEETS_PARENT",
]

# The edge of a fold curve of doubled orbits: where the orbit becomes its parent's, at a degenerate
# period doubling of the parent, the fold system is singular and the curve ends.
MEETS_PARENT = "the doubled orbit meets its parent (a degenerate period doubling)"


def _through_unit_circle(label, mu, others):
    """The message of an LPNS/PDNS point, or None for a neutral saddle of the other multipliers."""
    pair = [m for m in others if m.imag > 1e-7 * max(1.0, abs(m)) and abs(abs(m) - 1) < 1e-3]
    if not pair:
        return None
    return f"{label}: {mu[0].real:.6f} with exp(+-i {np.angle(pair[0]):.6f})"


def repeats_early(problem, x, tol: float = 1e-3) -> bool:
    """Whether the orbit x of a period-doubled problem (period 2k pi in an even number of equal
    arcs) repeats after half its period (to ``tol``): it is then its parent's orbit at a period
    doubling, where the doubled orbit's multiplier +1 is the parent's -1 squared with a second
    one beside it, and the fold system is singular. On a one-parameter branch that is where the
    branch is born or ends (its turn there, the pitchfork shape of a flip seen on the doubled
    map, is no fold); a fold curve of doubled orbits ends there, at a degenerate period doubling
    of the parent."""
    if problem.period_multiple < 2 or problem.period_multiple % 2:
        return False
    return half_period_gap(problem, x, 1.0) <= tol


class FoldCurveProblem(MinAugCurveProblem):
    """Points (x, p2) at p1 where the orbit has the multiplier +1: a curve of folds. A curve of
    folds of doubled orbits ends at the domain's edge where the orbit becomes its parent's
    (:func:`repeats_early`; the edge's name :data:`MEETS_PARENT`)."""

    kind, mu = "LP", 1.0
    test_kinds = ("CP", "LPPD", "LPNS")

    def in_domain(self, x, p) -> bool:
        if not super().in_domain(x, p):
            return False
        if repeats_early(self.orbits, x[: -self._extra]):
            self._edge = MEETS_PARENT
            return False
        return True

    def test_functions(self, x, p):
        others, ns = self.other_multipliers(x, p)
        return self._second(x, p)[3], np.prod(1 + others).real, ns

    def confirm(self, kind, x, p):
        mu = self.eigenvalues(x, p)
        if kind == "CP":
            return "cusp: the fold's quadratic coefficient vanishes (two folds meet)"
        if kind == "LPPD":
            k = int(np.argmin(np.abs(mu[1:] + 1)))
            return f"fold-flip: multipliers {mu[0].real:.6f} and {mu[1:][k].real:.6f}"
        return _through_unit_circle("fold-Neimark-Sacker", mu, mu[1:])


class FlipCurveProblem(MinAugCurveProblem):
    """Points (x, p2) at p1 where the orbit has the multiplier -1: a curve of period doublings."""

    kind, mu = "PD", -1.0
    test_kinds = ("LPPD", "PDNS")

    def test_functions(self, x, p):
        others, ns = self.other_multipliers(x, p)
        return np.prod(others - 1).real, ns

    def confirm(self, kind, x, p):
        mu = self.eigenvalues(x, p)
        if kind == "LPPD":
            k = int(np.argmin(np.abs(mu[1:] - 1)))
            return f"fold-flip: multipliers {mu[0].real:.6f} and {mu[1:][k].real:.6f}"
        return _through_unit_circle("flip-Neimark-Sacker", mu, mu[1:])


class PitchforkCurveProblem(MinAugCurveProblem):
    """Points (x, p2) at p1 where a symmetric orbit (x: the half period's arcs) breaks its
    symmetry: phi_pi has the multiplier +1."""

    kind, mu, symmetric = "BP", 1.0, True
    test_kinds = ("BPLP",)

    def test_functions(self, x, p):  # phi_pi's multiplier -1 is G's +1: the symmetric orbit folds
        others, _ = self.other_multipliers(x, p)
        return (np.prod(1 + others).real,)

    def confirm(self, kind, x, p):
        return "the symmetry-breaking curve meets a fold of the symmetric orbits"
