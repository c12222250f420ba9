"""The wall's restitution law identified from impact records: pairs of incoming and outgoing
particle speeds (v0, v+), fitted by eq. (21),

    1 - kappa(v0)**2 = delta(v0) = C v0**q,   q = pbar / (n + 1),
    C = 4 lam ((n + 1) / chi)**a I(n, pbar),  a = q / 2 + 1 / 2,                      (21), (19)

with kappa = v+ / v0. The records determine two numbers only: the exponent q, which fixes the
integer pair (n, pbar) up to their ratio, and the prefactor C, in which lam and chi enter as the
one combination lam chi**(-a). With q fixed, delta is linear in C, so C is the weighted linear
least-squares estimate for each candidate pbar (profiled over the integers), and its standard error
follows from the residuals. lam and chi are not separately identifiable from these records: the
fit reports the combination, and lam when chi is given (or chi when lam is).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from scipy import stats

from slosh_bif.identify.csv_table import number, read_table
from slosh_bif.model import restitution
from slosh_bif.model.params import Params

__all__ = ["ImpactRecords", "WallFit", "read_impact_records", "fit_wall", "FREE_NAMES"]

FREE_NAMES = ("lam", "chi", "pbar")  # what impact records can speak to (n is the wall's power, given)
PBAR_MAX = 12  # the profile over pbar runs over 0 .. PBAR_MAX


@dataclasses.dataclass(frozen=True)
class ImpactRecords:
    """Measured impacts: incoming speeds ``v0``, outgoing speeds ``v_out`` (> 0, at most v0), and
    the standard deviation of each outgoing speed (None: equal, estimated from the residuals)."""

    v0: np.ndarray
    v_out: np.ndarray
    std: np.ndarray | None = None
    source: str = ""

    @property
    def kappa(self) -> np.ndarray:
        return self.v_out / self.v0


def read_impact_records(path) -> ImpactRecords:
    """The records of a CSV file with a header holding ``v0`` and ``v_out`` (and optionally
    ``std``, the outgoing speed's standard deviation); a one-line ValueError naming the file and
    the row or column otherwise, before any fitting."""
    path = Path(path)
    columns, rows = read_table(path, ("v0", "v_out"), "impact records", optional=("std",))
    values = {name: [] for name in ("v0", "v_out", "std")}
    for k, row in enumerate(rows, start=2):  # line numbers, the header being line 1
        for name in ("v0", "v_out") + (("std",) if "std" in columns else ()):
            values[name].append(number(path, k, name, row[name], positive=True))
        if values["v_out"][-1] > values["v0"][-1]:
            raise ValueError(
                f"{path}, line {k}: the outgoing speed {values['v_out'][-1]:g} exceeds the "
                f"incoming {values['v0'][-1]:g} (a wall gives no energy)"
            )
    if len(values["v0"]) < 3:
        raise ValueError(
            f"{path}: {len(values['v0'])} impact records; the fit needs at least 3 (two numbers "
            "are estimated)"
        )
    std = np.array(values["std"]) if values["std"] else None
    return ImpactRecords(np.array(values["v0"]), np.array(values["v_out"]), std, str(path))


@dataclasses.dataclass(frozen=True)
class WallFit:
    """The fitted wall: the estimates (``values``: lam, chi, n, pbar), the identifiable prefactor
    ``C`` of (21) with its standard error and 95 % interval, the exponent ``q`` = pbar/(n+1), the
    free parameter's estimate and interval (``estimate``), the residual sum of squares of every
    pbar tried (``profile``), and what the records cannot tell (``not_identifiable``)."""

    values: dict
    C: float
    C_std: float
    C_interval: tuple
    q: float
    estimate: dict
    profile: dict
    rms: float
    not_identifiable: str
    records: int

    def params(self, base: Params) -> Params:
        return base.replace(**self.values)

    def as_dict(self) -> dict:
        return {
            "values": self.values,
            "C": self.C,
            "C_std": self.C_std,
            "C_interval_95": list(self.C_interval),
            "q": self.q,
            "estimate": self.estimate,
            "profile_rss_by_pbar": {str(k): v for k, v in self.profile.items()},
            "rms_kappa_residual": self.rms,
            "not_identifiable": self.not_identifiable,
            "records": self.records,
            "model": "eq. (21): 1 - kappa^2 = C v0^q",
        }


def _misfit(records: ImpactRecords, q: float) -> float:
    """The fit's misfit at the exponent q, on the log-likelihood's scale: chi-square in kappa
    with the records' std, else N log(RSS) (the likelihood with the scale estimated)."""
    rss = _fit_C(records, q)[2]
    if records.std is not None:
        C = _fit_C(records, q)[0]
        kappa_fit = np.sqrt(np.clip(1.0 - C * records.v0**q, 0.0, None))
        return float(np.sum(((records.kappa - kappa_fit) * records.v0 / records.std) ** 2))
    return float(len(records.v0) * math.log(max(rss, 1e-300)))


def _fit_C(records: ImpactRecords, q: float):
    """(C, its standard error, residual sum of squares in kappa) for the exponent q: weighted
    linear least squares on delta_i = 1 - kappa_i**2 = C v0_i**q, each delta's standard deviation
    2 kappa_i std_i / v0_i (propagated from the outgoing speed's), or equal weights."""
    delta = 1.0 - records.kappa**2
    basis = records.v0**q
    if records.std is not None:
        sd = 2.0 * records.kappa * records.std / records.v0
        w = 1.0 / np.maximum(sd, 1e-300) ** 2
    else:
        w = np.ones_like(delta)
    C = float(np.sum(w * basis * delta) / np.sum(w * basis * basis))
    residual = delta - C * basis
    dof = len(delta) - 1
    if records.std is not None:
        C_std = float(1.0 / math.sqrt(np.sum(w * basis * basis)))
    else:
        s2 = float(np.sum(residual**2) / max(dof, 1))
        C_std = float(math.sqrt(s2 / np.sum(basis * basis)))
    kappa_fit = np.sqrt(np.clip(1.0 - C * basis, 0.0, None))
    return C, C_std, float(np.sum((records.kappa - kappa_fit) ** 2))


def _prefactor(lam, chi, n, pbar) -> float:
    """C of (21) for the wall (lam, chi, n, pbar)."""
    return float(restitution.dissipation_at_unit_speed(lam, chi, n, pbar))


def fit_wall(records: ImpactRecords, base: Params, free) -> WallFit:
    """Fit (21) to ``records``: ``free`` a subset of lam, chi, pbar (the rest from ``base``; n is
    the wall's power, always given). With pbar free it is profiled over 0..PBAR_MAX (of n's
    parity, as pbar = 2p - n requires) and the best kept; then C is estimated and turned into the free one of
    lam and chi (the other from
    ``base``). Both lam and chi free: only lam chi**(-a) is determined; the fit keeps chi at
    ``base``'s value, says so in ``not_identifiable``, and reports the combination."""
    free = tuple(free)
    unknown = [f for f in free if f not in FREE_NAMES]
    if unknown or not free:
        raise ValueError(
            f"--free takes one or more of {', '.join(FREE_NAMES)} for impact records; got "
            f"{', '.join(free) or 'nothing'}"
        )
    n = base.n
    # pbar = 2p - n with p a non-negative integer: the parity of n (Params checks the same)
    candidates = range(n % 2, PBAR_MAX + 1, 2) if "pbar" in free else (base.pbar,)
    profile = {pbar: _fit_C(records, pbar / (n + 1))[2] for pbar in candidates}
    misfit = {pbar: _misfit(records, pbar / (n + 1)) for pbar in candidates}
    pbar = min(misfit, key=misfit.get)
    # pbar values the records cannot tell from the best (likelihood ratio, 95 %: chi-square(1) 3.84)
    consistent = sorted(k for k, v in misfit.items() if v - misfit[pbar] <= 3.841458820694124)
    q = pbar / (n + 1)
    C, C_std, rss = _fit_C(records, q)
    dof = len(records.v0) - 1
    t = float(stats.t.ppf(0.975, dof)) if records.std is None else 1.959963984540054
    interval = (C - t * C_std, C + t * C_std)
    # C is linear in lam and in chi**(-a): C = lam chi**(-a) K with K from n, pbar alone.
    a = q / 2 + 0.5
    K = _prefactor(1.0, 1.0, n, pbar)
    lam, chi = base.lam, base.chi
    note = ""
    estimate = {}
    if "lam" in free or ("chi" not in free):
        lam = C * chi**a / K
        scale = chi**a / K
        estimate["lam"] = {
            "value": lam,
            "std": C_std * scale,
            "interval_95": [interval[0] * scale, interval[1] * scale],
        }
        if "chi" in free:
            note = (
                f"lam and chi enter (21) only as lam * chi^(-{a:.4g}) = {C / K:.6g}: impact "
                "records fix that combination, not each; chi is kept at "
                f"{chi:g} and lam fitted. A measured contact time or penetration depth (which "
                "depend on chi alone) would separate them."
            )
    else:  # chi alone free: chi = (lam K / C)^(1/a), its interval from C's (monotone)
        chi = (lam * K / C) ** (1.0 / a)
        bounds = sorted(((lam * K / c) ** (1.0 / a) if c > 0 else math.inf) for c in interval)
        estimate["chi"] = {"value": chi, "std": chi / a * C_std / C, "interval_95": bounds}
    if "pbar" in free:
        estimate["pbar"] = {
            "value": pbar,
            "consistent_95": consistent,
            "profile": f"least misfit over {n % 2}..{PBAR_MAX} in steps of 2 (the parity of n = {n})",
        }
        if len(consistent) > 1:
            note = (note + " " if note else "") + (
                f"pbar is not determined: {', '.join(map(str, consistent))} fit the records "
                "equally at 95 % (likelihood ratio); the other estimates and "
                f"intervals hold given pbar = {pbar}. Records over a wider range of impact speeds "
                "would tell them apart."
            )
    values = {"lam": float(lam), "chi": float(chi), "n": int(n), "pbar": int(pbar)}
    rms = math.sqrt(rss / len(records.v0))
    return WallFit(values, C, C_std, interval, q, estimate, profile, rms, note, len(records.v0))
