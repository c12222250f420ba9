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

__all__ = ["FoldCurveProblem", "FlipCurveProblem", "PitchforkCurveProblem"]


def _through_unit_circle(label, mu, others):
    """The message of an LPNS/PDNS point, or None for a neutral saddle of the other multipliers."""
    pair = [m for m in others if m.imag > 1e-7 * max(1.0, abs(m)) and abs(abs(m) - 1) < 1e-3]
    if not pair:
        return None
    return f"{label}: {mu[0].real:.6f} with exp(+-i {np.angle(pair[0]):.6f})"


class FoldCurveProblem(MinAugCurveProblem):
    """Points (x, p2) at p1 where the orbit has the multiplier +1: a curve of folds."""

    kind, mu = "LP", 1.0
    test_kinds = ("CP", "LPPD", "LPNS")

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
