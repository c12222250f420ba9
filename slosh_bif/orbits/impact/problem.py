"""Periodic orbits of the vibro-impact model (8) with the restitution law (2), (21): fixed points of
its stroboscopic map, for the continuation engine.

The map is the exact flow of :mod:`slosh_bif.flows.impact.flow` over the forcing period 2 pi
(fixed period, no phase condition), or over pi followed by the mirror y -> -y for the symmetric
orbits ``y(tau + pi) = -y(tau)`` (whose multiplier -1 is the symmetry-breaking pitchfork, as for
(9)). Its Jacobian is the product of the flights' propagators and of the impacts' saltation
matrices (the derivative of kappa in the impact speed included), and its derivative in the
continued parameter comes from the propagators' own parameter derivatives: no finite differences.

Where the branch leaves the problem's domain (the engine's edge): grazing (GR), where an orbit
touches |w| = 1 with zero speed and the number of impacts per period changes (the map is not
smooth there), and an impact reaching the section tau = phase, where the state on the section
jumps from before the impact to after it. Each edge is located exactly (Newton on the map with
the edge's condition: a flight's turning point at the wall, or w = +-1 on the section);
:mod:`slosh_bif.orbits.impact.branches` moves the section or crosses the grazing and goes on.
"""

from __future__ import annotations

import dataclasses
import functools
from collections import OrderedDict

import numpy as np
from scipy import optimize

from slosh_bif.flows.impact.band import inside_measured_wall, within_measured_band
from slosh_bif.flows.impact.flow import IMPACT_VARIANTS, LINEAR_PARAMETERS, WALL_PARAMETERS, ImpactFlow
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.map_derivatives import ImpactMapDerivatives
from slosh_bif.orbits.multipliers import (
    TEST_FLOOR,
    describe_crossing,
    is_stable,
    multiplier_tests,
)

__all__ = ["ImpactOrbitProblem", "StrobeMap", "GrazingGap", "SECTION", "GRAZING", "VARIANT_NAMES"]

SECTION, GRAZING = "an impact on the section", "grazing (GR)"
VARIANT_NAMES = {"paper": "(8)", "corrected": "the corrected impact model"}  # in messages and titles
_KEEP = 8  # evaluations and flows kept: one corrector step and its finite-difference-free tangent


@dataclasses.dataclass(frozen=True)
class StrobeMap:
    """One evaluation of the map at (x, p): the image ``y``, its Jacobian ``phi`` and parameter
    derivative ``dp`` (the mirror applied for a symmetric problem), the impacts over the map's
    time (rows t, side, w'-, w'+) and the flow's end code (0: reached the end)."""

    y: np.ndarray
    phi: np.ndarray
    dp: np.ndarray
    impacts: np.ndarray
    code: int

    @functools.cached_property
    def multipliers(self) -> np.ndarray:
        """The eigenvalues of ``phi``, largest modulus first (asked for by the tests and the
        stability of one point)."""
        mu = np.linalg.eigvals(self.phi)
        return mu[np.argsort(-np.abs(mu), kind="stable")]


@dataclasses.dataclass(frozen=True)
class GrazingGap:
    """The orbit's nearest approach to grazing: ``gap`` (>= 0) at time ``t``, ``kind`` "flight"
    (a turning point short of the wall) or "impact" (the depth beyond the wall an impact would have
    reached), and the number of impacts over the map's time."""

    gap: float
    t: float
    kind: str
    impacts: int


class ImpactOrbitProblem:
    """Periodic orbits of (8) with period ``period_multiple * 2 pi`` (or symmetric ones on the
    half-period map), continued in ``param``: a parameter of the flow between impacts (eps, beta,
    gamma, sigma, Abar) or of the wall's restitution law (lam, chi). x = [X, X', w, w'] at tau = ``phase``;
    ``impacts`` (when
    given) is the number of impacts over the map's time that the domain holds to."""

    branch_kind = "periodic orbits of (8)"
    names = ("X", "Xd", "w", "wd")

    def __init__(
        self,
        params: Params,
        param: str = "sigma",
        *,
        symmetric: bool = False,
        period_multiple: int = 1,
        box: tuple | None = None,
        phase: float = 0.0,
        impacts: int | None = None,
        variant: str = "paper",
    ):
        if not isinstance(params, Params):
            raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
        if variant not in IMPACT_VARIANTS:
            raise ValueError(f"variant must be one of {', '.join(IMPACT_VARIANTS)}; got {variant!r}")
        allowed = LINEAR_PARAMETERS + (WALL_PARAMETERS if variant == "paper" else ())
        if param not in allowed:
            raise ValueError(
                f"param must be one of {', '.join(allowed)} for orbits of (8), variant {variant!r} (n and "
                f"pbar are integers; the measured wall has no derivatives in its parameters); got {param!r}"
            )
        if not (isinstance(period_multiple, int) and 1 <= period_multiple <= 8):
            raise ValueError(f"period_multiple must be an integer in [1, 8]; got {period_multiple!r}")
        if symmetric and period_multiple != 1:
            raise ValueError("a symmetric problem (the half-period map) needs period_multiple = 1")
        if box is not None and not (len(box) == 2 and box[0] < box[1]):
            raise ValueError(f"box must be (low, high) with low < high for {param}; got {box!r}")
        params.require_positive_stiffness()
        self.params, self.param, self.box = params, param, box
        self.symmetric, self.period_multiple = symmetric, period_multiple
        self.closing = -1.0 if symmetric else 1.0
        self.period = np.pi if symmetric else 2 * np.pi * period_multiple
        self.test_kinds = ("BP", "NS") if symmetric else ("PD", "NS")
        self.test_floor = TEST_FLOOR
        self.phase, self.impacts = float(phase), impacts
        self.variant = variant
        self.edge_name = GRAZING
        self.state_bound = 1e3 * (1.0 + params.Abar)
        self.evaluations = 0
        self._flows: OrderedDict = OrderedDict()
        self._params: dict = {}
        self._nearest = None  # the last grazing gap computed, with its (p, x)
        self._maps: OrderedDict = OrderedDict()

    def replace(self, **changes) -> ImpactOrbitProblem:
        """The same problem (parameters, continued parameter, variant) with ``changes`` to the keyword
        arguments (symmetric, period_multiple, box, phase, impacts, params, param)."""
        kept = dict(
            params=self.params,
            param=self.param,
            symmetric=self.symmetric,
            period_multiple=self.period_multiple,
            box=self.box,
            phase=self.phase,
            impacts=self.impacts,
            variant=self.variant,
        )
        return ImpactOrbitProblem(**{**kept, **changes})

    def params_at(self, p: float) -> Params:
        key = float(p)
        if key not in self._params:
            if len(self._params) > 4 * _KEEP:
                self._params.clear()
            self._params[key] = self.params.replace(**{self.param: key})
        return self._params[key]

    def flow_at(self, p: float) -> ImpactFlow:
        key = float(p)
        if key not in self._flows:
            self._flows[key] = ImpactFlow(self.params_at(p), param=self.param, variant=self.variant)
            if len(self._flows) > _KEEP:
                self._flows.popitem(last=False)
        return self._flows[key]

    def map_derivatives(self, params, y0, t1, **kwargs):
        """The map's derivatives on this section (:class:`.map_derivatives.ImpactMapDerivatives`)."""
        return ImpactMapDerivatives(params, y0, t1, phase=self.phase, variant=self.variant, **kwargs)

    def evaluate(self, x, p) -> StrobeMap:
        """The map at (x, p), kept for the few calls that follow at the same point."""
        x = np.asarray(x, dtype=float)
        key = (float(p), x.tobytes())
        if key not in self._maps:
            y, phi, dp, impacts, code = self.flow_at(p).strobe(x, self.phase, self.period)
            self.evaluations += 1
            self._maps[key] = StrobeMap(
                self.closing * y, self.closing * phi, self.closing * dp, impacts, code
            )
            if len(self._maps) > _KEEP:
                self._maps.popitem(last=False)
        return self._maps[key]

    def admissible(self, x, p) -> bool:
        """(x, p) may be mapped: p inside the ``box``, a parameter set with a positive vessel
        stiffness, the particle between the walls (for the measured wall: or within the band beyond
        D(v_min) where a rebound at speed leaves it,
        :func:`~slosh_bif.flows.impact.band.within_measured_band`) and the state finite and within
        ``state_bound``."""
        if self.box is not None and not self.box[0] <= p <= self.box[1]:
            return False
        if not all(abs(float(v)) < self.state_bound for v in x):  # NaN compares False: refused
            return False
        try:
            params = self.params_at(p)  # a value outside the parameter's range raises
        except ValueError:
            return False
        if params.eps * params.sigma >= 1.0:  # the vessel's stiffness (Params.require_positive_stiffness)
            return False
        if self.wall_distance(x, p) >= 0.0:
            return True
        return self.variant != "paper" and within_measured_band(self.flow_at(p).wall, x)

    def in_domain(self, x, p) -> bool:
        if not self.admissible(x, p):
            return False
        m = self.evaluate(x, p)
        return m.code == 0 and (self.impacts is None or len(m.impacts) == self.impacts)

    def residual(self, x, p):
        m = self.evaluate(x, p)
        return m.y - x if m.code == 0 else np.full(4, np.nan)

    def jacobian(self, x, p):
        return self.evaluate(x, p).phi - np.eye(4)

    def dparam(self, x, p):
        return self.evaluate(x, p).dp

    def map_multipliers(self, x, p):
        """The multipliers of the map solved for: the period map's, or G's = -phi_pi's."""
        return self.evaluate(x, p).multipliers

    def eigenvalues(self, x, p):
        """The Floquet multipliers over the orbit's whole period (for a symmetric orbit G's squares)."""
        mu = self.map_multipliers(x, p)
        return mu * mu if self.symmetric else mu

    is_stable = staticmethod(is_stable)

    def test_functions(self, x, p):
        """(a multiplier of the map through -1, a complex pair through the unit circle)."""
        return multiplier_tests(self.map_multipliers(x, p))

    def confirm(self, kind, x, p):
        return describe_crossing(kind, self.map_multipliers(x, p), self.symmetric)

    # -- the domain's edges -------------------------------------------------------------------

    def edge_distance(self, x, p) -> float:
        """How near (x, p) is to an edge: the smaller of the grazing gap and 1 - |w| on the section."""
        return min(self.grazing(x, p).gap, self.wall_distance(x, p))

    def edge_point(self, x, p):
        """The grazing point nearest (x, p), located; None at an impact on the section, whose exact
        place is of no interest (the section moves there). ``edge_name`` says which edge it is.

        From a flight turning short of the wall: Newton on [map(x) - x, gap] in (x, p). From an
        impact whose speed falls to zero (or where that Newton fails): the map's Jacobian grows as
        1 / (the slow impact's speed) along the very direction the gap's gradient points, and
        Newton on the section stalls; the grazing orbit is located where it is smooth, written at
        its contact with the gap set to zero."""
        nearest = self.grazing(x, p)
        on_section = self.wall_distance(x, p) < nearest.gap
        self.edge_name = SECTION if on_section else GRAZING
        if on_section:
            return None
        found = self._grazing_from_flight(x, p) if nearest.kind == "flight" else None
        if found is not None:
            return found
        from slosh_bif.orbits.impact.grazing_crossing import grazing_by_unfolding  # it builds on this module

        return grazing_by_unfolding(self, x, p)

    def _grazing_from_flight(self, x, p):
        """Newton on [map(x) - x, gap] from a flight's side of the grazing, keeping the best iterate
        (None where it does not reach 1e-8)."""

        def condition(x, p):
            # linear in the distance to the grazing on both sides: the gap of a flight, and at an
            # impact the square root of its depth (the depth goes as the distance squared, as the
            # speed does as the distance)
            g = self.grazing(x, p)
            return g.gap if g.kind == "flight" else -np.sqrt(g.gap)

        # Newton, keeping the best iterate: an iterate a hair beyond the grazing has a new impact
        # of speed sqrt(gap), whose square-root term in the map puts the residual far above the
        # last iterate's; near grazing from the impacting side the residual's floor is rounding
        # times 1 / (the slow impact's speed), the map's Jacobian there.
        u = np.append(np.asarray(x, dtype=float), float(p))
        best, best_size = None, np.inf
        for _ in range(12):
            if not self.admissible(*_split(u)):
                break
            m = self.evaluate(*_split(u))
            if m.code != 0:
                break
            F = np.append(m.y - u[:4], condition(*_split(u)))
            if not np.all(np.isfinite(F)):  # no approach to the wall left to measure
                break
            size = np.abs(F).max()
            if size < best_size:
                best, best_size = u.copy(), size
            if size < 1e-12:
                break
            row = self._gap_gradient(*_split(u))
            if row is None:
                row = np.empty(5)
                for j in range(5):  # the condition's gradient by central differences
                    e = np.zeros(5)
                    e[j] = 1e-7 * max(1.0, abs(u[j]))
                    row[j] = (condition(*_split(u + e)) - condition(*_split(u - e))) / (2 * e[j])
            J = np.vstack([np.column_stack([m.phi - np.eye(4), m.dp]), row])
            try:
                u = u - np.linalg.solve(J, F)
            except np.linalg.LinAlgError:
                break
        return _split(best) if best_size < 1e-8 else None

    def _gap_gradient(self, x, p):
        """d gap / d(x, p) where the nearest approach is a flight's turning point short of the wall:
        ``-sign(w) dw(t*)/d(x, p)`` (w' = 0 there, so the turning time's own change drops out),
        from the flow's Jacobian up to t*; None at an impact (the caller differentiates)."""
        g = self.grazing(x, p)
        if g.kind != "flight" or not np.isfinite(g.gap):
            return None
        y, phi, dp, _, code = self.flow_at(p).strobe(np.asarray(x, dtype=float), self.phase, g.t - self.phase)
        if code != 0:
            return None
        return -np.sign(y[2]) * np.append(phi[2], dp[2])

    def orbit(self, x, p, *, step: float = 0.01):
        """(t, y, impacts) of the orbit through x over the map's time, sampled every ``step`` and
        at the impacts (post-impact states), impacts rows t, side, w'-, w'+."""
        t, y, impacts, _ = ImpactFlow(self.params_at(p), step, variant=self.variant).run(
            np.asarray(x, dtype=float),
            self.phase,
            self.phase + self.period,
            stick_speed=1e-9,
            max_impacts=10_000,
        )
        return t, y, impacts

    def wall_distance(self, x, p) -> float:
        """How far the particle at x is inside the wall: ``1 - |w|``, or for the measured wall
        ``D(v) - |w|`` with v its speed towards the wall (clamped to the law's speeds)."""
        if self.variant == "paper":  # no flow needed (admissible() asks at trial points)
            return 1.0 - abs(float(x[2]))
        return inside_measured_wall(self.flow_at(p).wall, x)

    def grazing(self, x, p) -> GrazingGap:
        """The orbit's nearest approach to grazing: ``1 - |w|`` (for the measured wall ``D(v_min) -
        |w|``) at a turning point of a flight short of the wall, or the depth ``v**2 / (2 a)`` that
        an impact of speed v against an acceleration a away from the wall would have reached beyond
        it."""
        x = np.asarray(x, dtype=float)
        key = (float(p), x.tobytes())
        if self._nearest is None or self._nearest[0] != key:
            self._nearest = (key, self._grazing(x, p))
        return self._nearest[1]

    def _grazing(self, x, p) -> GrazingGap:
        flow = self.flow_at(p)
        t, y, impacts, _ = flow.run(
            np.asarray(x, dtype=float),
            self.phase,
            self.phase + self.period,
            stick_speed=1e-9,
            max_impacts=10_000,
        )
        best = GrazingGap(np.inf, 0.0, "flight", len(impacts))
        K = flow.K
        for tk, side, v_minus, _ in impacts:
            i = int(np.searchsorted(t, tk))
            z = np.array([y[0, i], y[1, i], y[2, i], v_minus, np.cos(tk), np.sin(tk)])
            away = -side * (K[3] @ z)  # acceleration away from the wall just before the impact
            if away > 0 and v_minus**2 / (2 * away) < best.gap:
                best = GrazingGap(v_minus**2 / (2 * away), float(tk), "impact", len(impacts))
        wd = y[3]
        level = flow.grazing_level
        reset = np.isin(t[1:], impacts[:, 0])  # the interval ends at an impact: w' jumps there
        turns = np.flatnonzero(
            (wd[:-1] * wd[1:] < 0) & (y[2, :-1] * wd[:-1] > 0) & (np.abs(y[2, 1:]) < level) & ~reset
        )
        for i in turns:
            s, w = _turning_point(K, t[i], y[:, i], t[i + 1] - t[i])
            if level - abs(w) < best.gap:
                best = GrazingGap(level - abs(w), float(t[i] + s), "flight", len(impacts))
        return best


def _split(u):
    return u[:4], u[4]


def _turning_point(K, t0, y0, h):
    """(s, w) where w' = 0 on the flight from (t0, y0) within (0, h), by Brent on the flight's
    Taylor polynomial ``sum_k s**k K**k z0 / k!`` (exact to rounding over one sample step, and a
    polynomial to evaluate instead of an expm per trial)."""
    z = np.concatenate([y0, [np.cos(t0), np.sin(t0)]])
    size = float(np.abs(K).sum(axis=1).max()) * h
    terms, term = [z], 1.0
    while term > 1e-18 * max(1.0, size) and len(terms) < 120:
        z = K @ z / len(terms)
        terms.append(z)
        term *= size / len(terms)
    w, wd = np.array(terms)[::-1, 2], np.array(terms)[::-1, 3]  # highest power first (polyval)
    s = optimize.brentq(lambda s: np.polyval(wd, s), 0.0, h, xtol=1e-15, rtol=1e-15)
    return s, float(np.polyval(w, s))
