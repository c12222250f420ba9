"""Grazing curves of the vibro-impact model (8) in two parameters: where a periodic orbit's flight
touches a wall |w| = 1 with zero speed, so that its number of impacts per period changes (eqs. 8,
21; the GR points of :mod:`slosh_bif.orbits.impact.branches`, continued in a second parameter).

The section is put at the grazing point itself. There the state is ``y_g = [X, X', side, 0]`` at
tau = t_g (side = +-1, the wall touched), so the grazing condition holds by construction, and the
unknowns are u = (X, X', t_g, p2), continued in p1; the equations are the orbit's return,
``closing * map(y_g) - y_g = 0`` over the orbit's period (the half period with the mirror closing
-1 for a symmetric orbit, whose mirror grazing on the other wall is then the map's end).

The map is smooth near a grazing orbit only if the grazing itself is never taken for an impact:
an iterate of Newton a hair beyond the grazing orbit would meet the wall with a speed of the
square root of its error, and the map would jump. So the map's first and last ``FREE`` of tau
are flights of (8)'s linear part with the wall ignored (the propagator ``expm(K FREE)`` and its
parameter derivative), and the compiled flow with its impacts runs in between. The domain
requires what makes this the orbit of (8): the free stretches stay inside the walls but at the
grazing point itself, the particle leaves the wall inward (``side * w'' < 0`` there: where it
vanishes the grazing degenerates, and the curve ends), and the other impacts keep their number,
stay faster than :data:`~slosh_bif.orbits.impact.strobe.MIN_IMPACT_SPEED` and, for the
corrected impact model, each on its side of its measured law's least speed (the law's corner).

Derivatives are exact as elsewhere for (8): the flights' propagators, the impacts' saltation
matrices; d/dt_g of the map of a time-periodic flow is ``f(end) - Phi f(start)``.
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np
from scipy import linalg

from slosh_bif.flows.impact.flow import IMPACT_VARIANTS, ImpactFlow
from slosh_bif.flows.impact.propagators import WALL_PARAMETERS, derivative_of_K
from slosh_bif.model.params import Params, real_pair
from slosh_bif.orbits.impact.strobe import off_the_curves

__all__ = ["GrazingCurveProblem", "FREE", "DEGENERATE"]

FREE = 0.1  # the flights at the map's ends with the wall ignored, in tau
DEGENERATE = "a degenerate grazing: the particle no longer leaves the wall inward"
_KEEP = 8
NEUTRAL = 1e-8  # multipliers this near the unit circle count as on it
_SAMPLES = 16  # points at which each free stretch is checked to stay inside the walls


class _Pieces:
    """What the map needs at one parameter set: the flows of (8) (or of the corrected impact
    model) with their derivative in p1 and in p2, the free stretch's propagator E and its
    derivatives in p1, p2, K, and the wall's level (1, or the measured wall's least clearance)."""

    def __init__(self, params: Params, pair: tuple, variant: str):
        self.flows = tuple(ImpactFlow(params, param=name, variant=variant) for name in pair)
        self.K = self.flows[0].K
        self.level = self.flows[0].grazing_level
        self.corner = self.flows[0].slowest_smooth_impact
        self.E = linalg.expm(self.K * FREE)
        zero = np.zeros_like(self.K)
        self.dE = []
        for name in pair:
            if name in WALL_PARAMETERS:  # the flights do not depend on the wall
                self.dE.append(np.zeros_like(self.K))
                continue
            exact = variant == "corrected"
            block = np.block([[self.K, zero], [derivative_of_K(params, name, exact), self.K]])
            self.dE.append(linalg.expm(block * FREE)[6:, :6])
        self.samples = [linalg.expm(self.K * s) for s in np.linspace(0.0, FREE, _SAMPLES + 1)[1:-1]]


class GrazingCurveProblem:
    """Orbits of (8) grazing the wall ``side`` at tau = t_g, continued in (p1, p2); a problem of
    the continuation engine in x = (X, X', t_g, p2) with parameter p1 (the module docstring).
    ``impacts``: the number of the other impacts the domain holds (None: any); ``slow``: how many
    of them are slower than the measured law's least speed
    (:func:`~slosh_bif.orbits.impact.strobe.slow_impacts`; 0 for (8))."""

    branch_kind = "grazing orbits of (8)"
    kind = "GR"
    test_kinds = ()

    def __init__(
        self,
        params: Params,
        p1: str,
        p2: str,
        *,
        side: float,
        symmetric: bool = False,
        period_multiple: int = 1,
        impacts: int | None = None,
        box: tuple | None = None,
        p2_box: tuple | None = None,
        variant: str = "paper",
        slow: int = 0,
    ):
        if not isinstance(params, Params):
            raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
        self.p1, self.p2 = real_pair((p1, p2))
        if side not in (1.0, -1.0):
            raise ValueError(f"side must be +1 or -1 (the wall touched); got {side!r}")
        if symmetric and period_multiple != 1:
            raise ValueError("a symmetric grazing orbit is one of the half-period map (period_multiple = 1)")
        if variant not in IMPACT_VARIANTS:
            raise ValueError(f"variant must be one of {', '.join(IMPACT_VARIANTS)}; got {variant!r}")
        self.params, self.side, self.variant = params, float(side), variant
        self.symmetric, self.period_multiple = bool(symmetric), int(period_multiple)
        self.closing = -1.0 if symmetric else 1.0
        self.period = np.pi if symmetric else 2 * np.pi * period_multiple
        self.impacts, self.box, self.p2_box, self.slow = impacts, box, p2_box, int(slow)
        self.names = ("X", "Xd", "t_g", p2)
        self.edge_name = "grazing curve's domain"
        self._pieces: OrderedDict = OrderedDict()
        self._maps: OrderedDict = OrderedDict()

    # -- the map -----------------------------------------------------------------------------

    def params_at(self, u, p) -> Params:
        return self.params.replace(**{self.p1: float(p), self.p2: float(u[3])})

    def _pieces_at(self, params: Params) -> _Pieces:
        if params not in self._pieces:
            self._pieces[params] = _Pieces(params, (self.p1, self.p2), self.variant)
            if len(self._pieces) > _KEEP:
                self._pieces.popitem(last=False)
        return self._pieces[params]

    def _field(self, K, y, tau):
        return (K @ np.concatenate([y, [np.cos(tau), np.sin(tau)]]))[:4]

    def evaluate(self, u, p):
        """(residual, Jacobian in u, derivative in p1, monodromy, impacts in between, code)."""
        u = np.asarray(u, dtype=float)
        key = (float(p), u.tobytes())
        if key in self._maps:
            return self._maps[key]
        at = self.params_at(u, p)
        pc = self._pieces_at(at)
        t_g = float(u[2])
        y_g = np.array([u[0], u[1], self.side * pc.level, 0.0])
        a = self.leaving(u, p)
        t_mid = t_g + self.period - FREE
        y2, phi, dp1, impacts, code = pc.flows[0].strobe(a[:4], t_g + FREE, self.period - 2 * FREE)
        if code == 0:
            _, _, dp2, _, code2 = pc.flows[1].strobe(a[:4], t_g + FREE, self.period - 2 * FREE)
            code = code2
        if code != 0:
            out = (np.full(4, np.nan), np.full((4, 4), np.nan), np.full(4, np.nan), None, impacts, code)
        else:
            b = pc.E @ np.concatenate([y2, [np.cos(t_mid), np.sin(t_mid)]])
            E4 = pc.E[:4, :4]
            M = E4 @ phi @ E4  # d y_end / d y_g
            c = self.closing
            residual = c * b[:4] - y_g
            J = np.empty((4, 4))
            J[:, :2] = c * M[:, :2] - np.eye(4)[:, :2]
            J[:, 2] = c * (self._field(pc.K, b[:4], t_g + self.period) - M @ self._field(pc.K, y_g, t_g))
            derivs = []
            for dE, dp in zip(pc.dE, (dp1, dp2)):
                inner = (dE @ np.concatenate([y_g, [np.cos(t_g), np.sin(t_g)]]))[:4]
                outer = (dE @ np.concatenate([y2, [np.cos(t_mid), np.sin(t_mid)]]))[:4]
                derivs.append(c * (outer + E4 @ (dp + phi @ inner)))
            J[:, 3] = derivs[1]
            out = (residual, J, derivs[0], c * M, impacts, 0)
        self._maps[key] = out
        if len(self._maps) > _KEEP:
            self._maps.popitem(last=False)
        return out

    def leaving(self, u, p):
        """The state at tau = t_g + FREE of the grazing orbit u, after its free flight off the wall
        (the compiled flow, started on the wall at zero speed, would see an impact there)."""
        t_g = float(u[2])
        pc = self._pieces_at(self.params_at(u, p))
        return (pc.E @ np.array([u[0], u[1], self.side * pc.level, 0.0, np.cos(t_g), np.sin(t_g)]))[:4]

    def level_at(self, u, p) -> float:
        """|w| at the grazing point (1 for (8), the measured wall's least clearance otherwise)."""
        return self._pieces_at(self.params_at(u, p)).level

    def residual(self, u, p):
        return self.evaluate(u, p)[0]

    def jacobian(self, u, p):
        return self.evaluate(u, p)[1]

    def dparam(self, u, p):
        return self.evaluate(u, p)[2]

    # -- the domain -----------------------------------------------------------------------------

    def leaves_inward(self, u, p) -> float:
        """``-side * w''`` at the grazing point: positive where the particle leaves the wall inward."""
        pc = self._pieces_at(self.params_at(u, p))
        return -self.side * self._field(pc.K, np.array([u[0], u[1], self.side * pc.level, 0.0]), u[2])[3]

    def in_domain(self, u, p) -> bool:
        """u finite, p1 and p2 in their boxes, a positive vessel stiffness, the grazing a regular
        one, the free stretches inside the walls and the impacts in between as at the start."""
        u = np.asarray(u, dtype=float)
        if not np.all(np.isfinite(u)) or np.abs(u[:2]).max() > 1e3 * (1 + self.params.Abar):
            return False
        for value, box in ((p, self.box), (u[3], self.p2_box)):
            if box is not None and not box[0] <= value <= box[1]:
                return False
        try:
            at = self.params_at(u, p)
            at.require_positive_stiffness()
        except ValueError:
            return False
        if not self.leaves_inward(u, p) > 0:
            return False
        residual, _, _, _, impacts, code = self.evaluate(u, p)
        if code != 0 or not np.all(np.isfinite(residual)):
            return False
        if self.impacts is not None and len(impacts) != self.impacts:
            return False
        if off_the_curves(impacts[:, 2], self._pieces_at(self.params_at(u, p)).corner, self.slow):
            return False
        return self._free_stretches_inside(u, p)

    def _free_stretches_inside(self, u, p) -> bool:
        pc = self._pieces_at(self.params_at(u, p))
        t_g = float(u[2])
        start = np.array([u[0], u[1], self.side * pc.level, 0.0, np.cos(t_g), np.sin(t_g)])
        # the end stretch, run backwards from the grazing point it closes on (the mirror's for a
        # symmetric orbit): the state at its start is expm(-K FREE) applied to the end state
        end_state = self.closing * start[:4]
        t_end = t_g + self.period
        end = np.concatenate([end_state, [np.cos(t_end), np.sin(t_end)]])
        back = linalg.solve(pc.E, end)
        for P in pc.samples:
            if abs((P @ start)[2]) >= pc.level or abs((P @ back)[2]) >= pc.level:
                return False
        return True

    def edge_name_at(self, u, p) -> str:
        return DEGENERATE if not self.leaves_inward(u, p) > 0 else self.edge_name

    # -- stability -------------------------------------------------------------------------------

    def eigenvalues(self, u, p):
        """The grazing orbit's multipliers over its whole period, on the side without the grazing
        impact (the map's monodromy; squared for a symmetric orbit)."""
        M = self.evaluate(u, p)[3]
        if M is None:
            return np.full(4, np.nan + 0j)
        mu = np.linalg.eigvals(M)
        mu = mu * mu if self.symmetric else mu
        return mu[np.argsort(-np.abs(mu), kind="stable")]

    @staticmethod
    def is_stable(multipliers) -> bool:
        """All multipliers inside the unit circle by more than rounding. (8) has no damping of the
        particle between impacts, so an orbit without impacts (the linear response grazing the
        wall where contact begins) has a multiplier pair on the circle: neutral, not stable."""
        return bool(np.all(np.abs(multipliers) < 1.0 - NEUTRAL))
