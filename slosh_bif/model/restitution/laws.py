"""The two questions the rest of the package asks of a wall, as one interface each, and the
factories that answer them for a model.

* :class:`SpeedLaw`: what one impact does, as a function of the impact speed v0: the restitution
  kappa(v0) and the clearance D(v0) at which a rigid wall would give the same flights. Eq. (21)
  (:class:`~slosh_bif.model.restitution.eq21.Eq21Law`, D = 1) or the smooth wall of (10) measured
  contact by contact (:class:`~slosh_bif.model.restitution.wall.WallLaw`).
* :class:`ManifoldRestitution`: the same law on the stable branch S+ of the slow invariant
  manifold (36), where the impact speed is a function (38) of the amplitude A: kappa(A), rho(A)
  (31), D(A), their slopes, and the window of A where S+ exists with its named ends. Eq. (39)
  (:class:`~slosh_bif.model.restitution.on_manifold.ManifoldLaw`) or the measured wall
  (:class:`~slosh_bif.model.restitution.corrected.CorrectedLaw`).

The slow flow, the critical forcing and the regime classifier ask :func:`manifold_law` for one
object and nothing else.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from slosh_bif.model.restitution.checks import check_params

__all__ = ["MODELS", "SpeedLaw", "ManifoldRestitution", "check_model", "speed_law", "manifold_law"]

MODELS = ("slowflow", "corrected")
"""``slowflow``: eq. (46) as derived (kappa of (21)/(39), wall at |w| = 1); ``corrected``: kappa and
clearance of the measured wall."""


@runtime_checkable
class SpeedLaw(Protocol):
    """kappa and the clearance D as functions of the impact speed v0 > 0 (vectorised)."""

    def kappa(self, v0): ...

    def clearance(self, v0): ...

    def slopes(self, v0, *, checked: bool = True):
        """(kappa, d kappa/dv0, D, dD/dv0) at v0."""


@runtime_checkable
class ManifoldRestitution(Protocol):
    """The law on S+: functions of the amplitude A inside ``[lower.A, upper.A]``."""

    lower: object  # the ManifoldEnd where S+ ends below (A, kappa there, its kind)
    upper: object  # ... and above (None, or A = inf, when it does not)

    def kappa(self, A): ...

    def rho(self, A): ...

    def alpha(self, A): ...

    def values(self, A):
        """(kappa, rho) at A."""

    def slopes(self, A):
        """The derivatives the slow flow's Jacobian needs at A."""

    def describe(self) -> str: ...


def check_model(model: str) -> str:
    """``model`` if it names a law (:data:`MODELS`); else a one-line ValueError."""
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    return model


def speed_law(params, model: str = "slowflow") -> SpeedLaw:
    """kappa(v0) and D(v0) of ``model``'s wall: eq. (21) with D = 1, or the measured wall over the
    speeds the corrected slow flow uses."""
    from slosh_bif.model.restitution.corrected import measured_wall
    from slosh_bif.model.restitution.eq21 import Eq21Law

    check_params(params)
    if check_model(model) == "slowflow":
        return Eq21Law(params.lam, params.chi, params.n, params.pbar)
    return measured_wall(params.lam, params.chi, params.n, params.pbar)


def manifold_law(params, model: str = "slowflow") -> ManifoldRestitution:
    """The law on S+ of ``model``: a :class:`~slosh_bif.model.restitution.on_manifold.ManifoldLaw`
    or a :class:`~slosh_bif.model.restitution.corrected.CorrectedLaw` (which depends on the wall
    alone: one per wall and process)."""
    from slosh_bif.model.restitution.corrected import CorrectedLaw
    from slosh_bif.model.restitution.on_manifold import ManifoldLaw

    if check_model(model) == "slowflow":
        return ManifoldLaw(params)
    check_params(params)
    key = (params.lam, params.chi, params.n, params.pbar)
    if key not in _LAWS:
        if len(_LAWS) >= 32:
            _LAWS.pop(next(iter(_LAWS)))
        _LAWS[key] = CorrectedLaw(params)
    return _LAWS[key]


_LAWS: dict = {}  # CorrectedLaw per wall (lam, chi, n, pbar): the law does not depend on the rest
