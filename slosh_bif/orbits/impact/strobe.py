"""The stroboscopic map of the vibro-impact model (8) as the orbit equations of the curves in two
parameters (:mod:`.minaug`): with it the fold, flip, pitchfork and Neimark-Sacker curve classes
trace curves of (8) unchanged.

It is one arc in the terms of multiple shooting: the map over the forcing period (over pi for the
symmetric orbits, whose closing is the mirror y -> -y), from the section tau = ``phase``, with its
Jacobian and its derivatives in both parameters exact (the flights' propagators and the impacts'
saltation matrices, the derivative of kappa (21) in the impact speed included:
:class:`~slosh_bif.orbits.impact.problem.ImpactOrbitProblem`). The domain holds the number of
impacts per period fixed: where it changes (grazing) or an impact reaches the section, the map is
not smooth, and a curve ends there at the domain's edge.
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from slosh_bif.model.params import Params, real_pair
from slosh_bif.orbits.impact.problem import SECTION, ImpactOrbitProblem
from slosh_bif.orbits.shooting import Arcs

__all__ = ["ImpactStrobe", "MIN_IMPACT_SPEED", "NEAR_GRAZING", "slow_impacts", "off_the_curves"]

_KEEP = 8  # parameter sets whose problems are kept (a corrector step and its differences)

# Near grazing the saltation matrices grow like 1 / (impact speed) and the map's second
# derivatives (central differences) lose all accuracy: a curve ends where its slowest impact
# falls below this speed (the Fig. 13 fold curves crept to a stop at 0.004, with a multiplier 1e6).
MIN_IMPACT_SPEED = 1e-2
NEAR_GRAZING = f"grazing (GR): an impact slower than {MIN_IMPACT_SPEED:g}, or the number of impacts changes"


def slow_impacts(speeds, corner: float) -> int:
    """How many of the impacts' ``speeds`` lie between :data:`MIN_IMPACT_SPEED` and ``corner``, the
    corrected impact model's measured law's least speed (0 for (8)): the law is held constant below
    it, so the map is smooth on either side and has a corner there."""
    speeds = np.abs(np.asarray(speeds, dtype=float))
    return int(np.count_nonzero((speeds >= MIN_IMPACT_SPEED) & (speeds < corner)))


def off_the_curves(speeds, corner: float, slow: int) -> bool:
    """Whether impacts of ``speeds`` leave a curve's domain: one slower than
    :data:`MIN_IMPACT_SPEED` (a grazing), or another number than ``slow`` below the law's corner
    speed ``corner`` (:func:`slow_impacts`: an impact crossed the corner)."""
    speeds = np.abs(np.asarray(speeds, dtype=float))
    return bool(len(speeds) and speeds.min() < MIN_IMPACT_SPEED) or slow_impacts(speeds, corner) != slow


class ImpactStrobe:
    """Orbits of (8) through x = [X, X', w, w'] at tau = ``phase`` for the curve problems, with
    the interface of :class:`~slosh_bif.orbits.shooting.ShootingProblem` they use: one arc,
    ``sensitivities`` = (p1, p2). ``impacts``: the number of impacts over the map's time that
    the domain holds to (None: any); ``slow``: the number of them slower than the corrected
    impact model's measured law's least speed that it holds to (:func:`slow_impacts`; 0 for
    (8)); ``variant``: (8) as stated or the corrected impact model
    (:class:`~slosh_bif.orbits.impact.problem.ImpactOrbitProblem`)."""

    branch_kind = "periodic orbits of (8)"
    names = ("X", "Xd", "w", "wd")
    segments = 1

    def __init__(
        self,
        params: Params,
        sensitivities: tuple,
        *,
        symmetric: bool = False,
        period_multiple: int = 1,
        box: tuple | None = None,
        phase: float = 0.0,
        impacts: int | None = None,
        variant: str = "paper",
        slow: int = 0,
    ):
        self.sensitivities = real_pair(sensitivities, "sensitivities")
        self.variant = variant
        self.params, self.param = params, self.sensitivities[0]
        self.symmetric, self.period_multiple = bool(symmetric), period_multiple
        self.closing = -1.0 if symmetric else 1.0
        self.box, self.phase, self.impacts, self.slow = box, float(phase), impacts, int(slow)
        # One problem per parameter of the pair: each gives the map's derivative in its own.
        self._problems: OrderedDict = OrderedDict()
        self._maps_of(params)  # a bad parameter set or pair fails here, before any work
        self._probe = ImpactOrbitProblem(
            params,
            self.param,
            symmetric=self.symmetric,
            period_multiple=period_multiple,
            box=box,
            phase=self.phase,
            variant=variant,
        )
        self.corner = self._probe.flow_at(getattr(params, self.param)).slowest_smooth_impact
        self.edge_rule = (
            NEAR_GRAZING
            if self.corner == 0
            else f"an impact at the measured wall law's least speed {self.corner:g} (the law is held "
            f"constant below it: the map has a corner there), one slower than {MIN_IMPACT_SPEED:g}, or "
            "the number of impacts changes"
        )

    def _maps_of(self, params: Params):
        key = params
        if key not in self._problems:
            self._problems[key] = tuple(
                ImpactOrbitProblem(
                    params,
                    name,
                    symmetric=self.symmetric,
                    period_multiple=self.period_multiple,
                    phase=self.phase,
                    variant=self.variant,
                )
                for name in self.sensitivities
            )
            if len(self._problems) > _KEEP:
                self._problems.popitem(last=False)
        return self._problems[key]

    def arcs(self, x, params: Params) -> Arcs:
        """The map at (x, params) as one arc: its end (before the mirror), its Jacobian and its
        derivatives in (p1, p2); NaN where the flow stops short (sticking, a complex kappa), the
        number of impacts is not the domain's or its impacts leave the curves' domain
        (:func:`off_the_curves`)."""
        x = np.asarray(x, dtype=float)
        first, second = self._maps_of(params)
        m1 = first.evaluate(x, getattr(params, self.sensitivities[0]))
        m2 = second.evaluate(x, getattr(params, self.sensitivities[1])) if m1.code == 0 else m1
        grazing = (self.impacts is not None and len(m1.impacts) != self.impacts) or off_the_curves(
            m1.impacts[:, 2], self.corner, self.slow
        )
        if m1.code != 0 or m2.code != 0 or grazing:
            nan = np.full((4, 4), np.nan)
            return Arcs(np.full((1, 4), np.nan), nan[None], np.full((1, 4, 2), np.nan), np.nan, nan)
        c = self.closing  # the problems give G = closing * map; the arc is the map itself
        phi = c * m1.phi
        return Arcs((c * m1.y)[None], phi[None], np.column_stack([c * m1.dp, c * m2.dp])[None], np.nan, phi)

    def residual_of(self, x, arcs: Arcs):
        return arcs.ends[0] - self.closing * np.asarray(x, dtype=float)

    def jacobian_of(self, arcs: Arcs, wrap: complex | None = None):
        """phi - wrap I: singular where the map's Jacobian has the multiplier ``wrap`` (the
        residual's own Jacobian by default: ``closing``)."""
        wrap = self.closing if wrap is None else wrap
        return arcs.mats[0] - wrap * np.eye(4)

    def in_domain(self, x, p) -> bool:
        """(x, p) may be mapped (:meth:`ImpactOrbitProblem.admissible`, p1 in ``box``); the map's
        own failures and another impact count show as a non-finite residual."""
        return self._probe.admissible(x, p)

    def edge_name_at(self, x, params: Params) -> str | None:
        """The edge near the orbit x at ``params``: ``edge_rule`` (grazing) when its slowest impact
        is within a factor 2 of :data:`MIN_IMPACT_SPEED`, an impact's speed within a factor 2 of the
        law's corner or it has no longer the domain's impacts, the section when the particle sits
        within 1e-3 of a wall there; None for neither."""
        if 1.0 - abs(float(x[2])) < 1e-6:  # an impact at the section: the count flips there
            return SECTION
        m = self._maps_of(params)[0].evaluate(
            np.asarray(x, dtype=float), getattr(params, self.sensitivities[0])
        )
        speeds = np.abs(m.impacts[:, 2])
        near_corner = np.any((speeds > 0.5 * self.corner) & (speeds < 2 * self.corner))
        if (
            (self.impacts is not None and len(m.impacts) != self.impacts)
            or (len(speeds) and speeds.min() < 2 * MIN_IMPACT_SPEED)
            or near_corner
            or slow_impacts(speeds, self.corner) != self.slow
        ):
            return self.edge_rule
        if 1.0 - abs(float(x[2])) < 1e-3:
            return SECTION
        return None

    def edge_distance_at(self, x, params: Params) -> float:
        """0 where :meth:`edge_name_at` names the grazing rule's edge, else how far the particle
        is inside the wall on the section (``1 - |w|``)."""
        if self.edge_name_at(x, params) == self.edge_rule:
            return 0.0
        return self._probe.wall_distance(x, getattr(params, self.param))

    def full_states(self, x):
        """The orbit's state on the section (the whole-period map's unknowns are the same four)."""
        return np.asarray(x, dtype=float)
