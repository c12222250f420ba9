"""A frequency-response fit's result (:mod:`.response_fit`) and the models it may be fitted by:
the slow flows (46) and the orbits of (9), (8) and the corrected impact model."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.identify.goodness import Goodness
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import dissipation_at_unit_speed

__all__ = [
    "SLOW_MODELS",
    "ORBIT_MODELS",
    "MODELS",
    "MODEL_NAMES",
    "MISFIT_UNSCALED",
    "ResponseFit",
    "dissipation_estimates",
    "free_names",
]

SLOW_MODELS = ("slowflow", "corrected")  # the slow flows (46)
ORBIT_MODELS = ("smooth", "impact", "impact-corrected")  # the orbits of (9), (8), the corrected (8)
MODELS = SLOW_MODELS + ORBIT_MODELS
MISFIT_UNSCALED = "N log(residual sum of squares), the likelihood's scale with the noise estimated"
MODEL_NAMES = {
    "slowflow": "the slow flow's steady states (46)",
    "corrected": "the corrected slow flow's steady states",
    "smooth": "the orbits of the smooth model (9)",
    "impact": "the orbits of the vibro-impact model (8)",
    "impact-corrected": "the orbits of the corrected impact model",
}


@dataclasses.dataclass(frozen=True)
class ResponseFit:
    """A fitted frequency response: ``values`` (the whole wall and vessel parameter set's fitted
    entries), ``estimate`` per free parameter (value, std, Wald and profile 95 % intervals),
    ``correlation`` (rows and columns in ``free`` order), the misfit, what is ``not_identifiable``,
    whether the fit ``converged`` (and why not) and the profiles (held value, misfit rise)."""

    free: tuple
    values: dict
    estimate: dict
    correlation: np.ndarray
    misfit: float
    rms: float
    points: int
    model: str
    not_identifiable: str
    converged: bool
    message: str
    profiles: dict
    scale_known: bool
    residuals: np.ndarray  # at the estimate, per point (divided by std when given)
    goodness: Goodness | None = None  # whether the fitted model describes the data
    assignment: list = dataclasses.field(default_factory=list)  # per point: what it is compared with
    minima: list = dataclasses.field(default_factory=list)  # the global search's best and runner-up
    ladder: list = dataclasses.field(default_factory=list)  # --model auto: every rung tried, and why

    @property
    def describes(self) -> bool:
        """False where the fitted model does not describe the data (its intervals are then
        conditional on a model that does not fit)."""
        return self.goodness is None or self.goodness.describes

    def params(self, base: Params) -> Params:
        return base.replace(**self.values)

    def as_dict(self) -> dict:
        return (
            {
                "model": f"{MODEL_NAMES[self.model]} (model {self.model!r})",
                "free": list(self.free),
                "values": self.values,
                "estimate": self.estimate,
                "correlation": self.correlation.tolist(),
                "misfit": self.misfit,
                "misfit_kind": "chi-square" if self.scale_known else MISFIT_UNSCALED,
                "rms_residual": self.rms,
                "points": self.points,
                "not_identifiable": self.not_identifiable,
                "converged": self.converged,
                "message": self.message,
                "profiles": {k: [list(map(float, row)) for row in v] for k, v in self.profiles.items()},
                "residuals": self.residuals.tolist(),
                "goodness_of_fit": None if self.goodness is None else self.goodness.as_dict(),
                "intervals": "95 %"
                if self.describes
                else "95 %, conditional on a model that does not describe the data",
                "assignment": self.assignment,
                "minima": self.minima,
            }
            | self._unscaled()
            | ({"ladder": self.ladder} if self.ladder else {})
        )

    def _unscaled(self) -> dict:
        """Without the data's std the misfit is N log(RSS); the RSS itself beside it."""
        if self.scale_known:
            return {}
        return {"residual_sum_of_squares": float(self.residuals @ self.residuals)}


def dissipation_estimates(params: Params, lam: dict) -> dict:
    """C of (21) (the energy fraction lost at unit impact speed) and kappa(1) = sqrt(1 - C), with
    intervals from lam's: C is proportional to lam."""
    C = float(dissipation_at_unit_speed(params.lam, params.chi, params.n, params.pbar))
    per_lam = C / params.lam
    out = {"C": {"value": C, "std": per_lam * lam["std"]}}
    kappa = {
        "value": math.sqrt(max(1.0 - C, 0.0)),
        "std": 0.5 * per_lam * lam["std"] / max(math.sqrt(max(1.0 - C, 0.0)), 1e-300),
    }
    for key in ("wald_95", "profile_95"):
        if key in lam:
            bounds = [None if v is None else per_lam * max(v, 0.0) for v in lam[key]]
            out["C"][key] = bounds
            kappa[key] = [None if c is None else math.sqrt(max(1.0 - c, 0.0)) for c in bounds[::-1]]
    out["kappa_at_unit_speed"] = kappa
    return out


def free_names(free, allowed, what: str) -> tuple:
    """``free`` without repeats, each one of ``allowed``; else a one-line ValueError naming them and
    ``what`` they are fitted to."""
    free = tuple(dict.fromkeys(free))
    if not free or any(f not in allowed for f in free):
        raise ValueError(
            f"--free takes one or more of {', '.join(allowed)} for {what}; got {', '.join(free) or 'nothing'}"
        )
    return free


def chi_held(free, base: Params, who: str, through_c: bool) -> tuple:
    """(names fitted, a sentence): where the model (``through_c``: it has the wall through C of
    (21) alone) is asked for both lam and chi, chi is held at ``base``'s and lam fitted, said of
    ``who``."""
    names = list(free)
    if not (through_c and "lam" in names and "chi" in names):
        return names, ""
    names.remove("chi")
    return names, (
        f"{who} with the law (21) depends on lam and chi only through C of (21): chi is held at "
        f"{base.chi:g} and lam fitted."
    )
