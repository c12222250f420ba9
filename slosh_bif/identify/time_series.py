"""The wall's (and the vessel's) parameters fitted to a record in time: a free decay (as Fig. 9
with the forcing off) or a forced record at one frequency (the transient onto a steady state, as
Fig. 9 itself). The vessel's amplitude A(tau) moves along the slow invariant manifold (36) under
the slow flow (45) from (A0, psi0): with Abar = 0, dA/dT1 (T1 = eps tau) does not depend on the
phase and carries the impacts' loss C of (21) and the vessel's gamma; with the forcing on, the
phase matters and psi0 is fitted too. Below S+'s end A_min the particle stops reaching the walls
and the amplitude relaxes, at the rate of the vessel's mode of (8)'s linear flight, to the
impact-free response (0 in a free decay): the leading order of a linear transient, its beating
left out.

Data: a CSV with ``tau`` and ``A`` (the envelope: the vessel's amplitude at each time) or ``tau``
and ``X`` (the vessel's displacement: its envelope taken from the peaks of |X|, each refined by a
parabola through its three samples, which the leading order X = A sin(tau + psi) (25) makes A),
optional ``std``. The initial amplitude A0 (and, forced, the phase psi0) at the first time is
fitted with the free parameters (nuisance parameters, with Wald intervals only); intervals and
profiles as for a frequency response (:mod:`.response_stats`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np

from slosh_bif.identify.csv_table import number, read_header, read_table
from slosh_bif.identify.goodness import goodness
from slosh_bif.identify.response_model import impact_free
from slosh_bif.identify.response_result import ResponseFit, chi_held, free_names
from slosh_bif.identify.response_stats import (
    ELASTIC,
    STARTS,
    least_squares,
    misfit_of,
    profile,
    range_end_sentences,
    wald,
)
from slosh_bif.model.equations import ImpactModel
from slosh_bif.model.params import Params
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow

__all__ = [
    "TimeRecord",
    "TimeSeriesFit",
    "read_time_record",
    "envelope",
    "record_amplitudes",
    "fit_time_series",
    "DECAY_FREE",
    "FORCED_FREE",
]

DECAY_FREE = ("lam", "chi", "gamma")  # and A0, always fitted
FORCED_FREE = DECAY_FREE + ("Abar",)  # and A0, psi0
PHASE_STARTS = 4  # starts of psi0 spread over the circle


@dataclasses.dataclass(frozen=True)
class TimeRecord:
    """A measured record: times ``tau``, envelope ``A``, optional ``std``, the source file."""

    tau: np.ndarray
    A: np.ndarray
    std: np.ndarray | None = None
    source: str = ""

    def __len__(self) -> int:
        return len(self.tau)


def read_time_record(path) -> TimeRecord:
    """``tau, A[, std]`` or ``tau, X`` (envelope from the peaks of |X|); one-line errors naming the
    file, line and column."""
    path = Path(path)
    signal = "X" in read_header(path) and "A" not in read_header(path)
    names = ("tau", "X") if signal else ("tau", "A")
    columns, rows = read_table(path, names, "a record in time", optional=() if signal else ("std",))
    numbers = names + (("std",) if "std" in columns and not signal else ())
    values = {name: [] for name in numbers}
    for k, row in enumerate(rows, start=2):
        for name in numbers:
            values[name].append(number(path, k, name, row[name], positive=name in ("A", "std")))
    tau = np.array(values["tau"])
    if len(tau) < 3 or np.any(np.diff(tau) <= 0):
        raise ValueError(f"{path}: tau must increase strictly over at least 3 rows")
    if signal:
        tau, A = envelope(tau, np.array(values["X"]))
        if len(tau) < 3:
            raise ValueError(f"{path}: fewer than 3 peaks of |X| to take the envelope from")
        return TimeRecord(tau, A, None, str(path))
    std = np.array(values["std"]) if "std" in values else None
    return TimeRecord(tau, np.array(values["A"]), std, str(path))


SEPARATION = 0.6  # peaks of |X| kept at least this fraction of the record's half-period apart


def envelope(tau, X) -> tuple:
    """(times, heights) of the peaks of |X|, one a half-period (the highest local maximum within
    :data:`SEPARATION` of the half-period of X's strongest frequency, so that noise's wiggles are
    not taken for peaks), each the vertex of the parabola through the peak sample and its
    neighbours."""
    from scipy import signal

    y = np.abs(X)
    spectrum = np.abs(np.fft.rfft(X - np.mean(X)))
    strongest = int(np.argmax(spectrum[1:])) + 1 if len(spectrum) > 1 else 1
    half = len(X) / (2 * strongest)  # in samples
    k, _ = signal.find_peaks(y, distance=max(1, int(SEPARATION * half)))
    k = k[(k > 0) & (k < len(y) - 1)]
    a, b, c = y[k - 1], y[k], y[k + 1]
    curvature = a - 2 * b + c
    shift = np.where(curvature < 0, 0.5 * (a - c) / np.where(curvature < 0, curvature, 1.0), 0.0)
    h = tau[k + 1] - tau[k]  # a uniform sample near each peak
    return tau[k] + shift * h, b - 0.25 * (a - c) * shift


def record_amplitudes(
    params: Params, A0: float, tau, model: str = "slowflow", *, forced: bool = False, psi0: float = 0.0
) -> np.ndarray:
    """A(tau) from (A0, psi0) at tau[0], the forcing off unless ``forced``: (45) on S+ until A_min,
    then a relaxation at the rate of the vessel's mode of (8)'s linear flight to the impact-free
    response (0 without forcing)."""
    tau = np.asarray(tau, dtype=float)
    free = params if forced else params.replace(Abar=0.0)
    T1 = free.eps * (tau - tau[0])
    out = np.empty(len(tau))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        flow = SlowFlow(free, model)
        if A0 <= flow.A_min:
            escape, A_escape = 0.0, A0
        else:
            run = flow.integrate(A0, psi0, (0.0, float(T1[-1]) or 1e-12), t_eval=T1)
            out[: len(run.A)] = run.A
            escape, A_escape = run.T1_end, flow.A_min
    after = T1 > escape if A0 > flow.A_min else np.ones(len(tau), dtype=bool)
    if after.any():
        rate = _linear_rate(free)
        target = impact_free(free)[0] if forced else 0.0
        out[after] = target + (A_escape - target) * np.exp(-rate * (T1[after] - escape) / free.eps)
    return out


def _linear_rate(params: Params) -> float:
    """The decay rate in tau of the vessel's mode of (8)'s linear flight (no impacts): its
    eigenvalue nearest i (the particle's own mode has no stiffness at beta = 0)."""
    eigenvalues = np.linalg.eigvals(ImpactModel(params).matrix)
    return float(-eigenvalues[np.argmin(np.abs(eigenvalues - 1j))].real)


@dataclasses.dataclass(frozen=True)
class TimeSeriesFit(ResponseFit):
    """A fitted record: as a :class:`~.response_fit.ResponseFit`, its ``values`` also holding A0
    (and psi0 for a ``forced`` record), the nuisance parameters."""

    forced: bool = False

    def params(self, base: Params) -> Params:
        return base.replace(**{k: v for k, v in self.values.items() if k not in NUISANCE})

    def as_dict(self) -> dict:
        kind = "a forced record" if self.forced else "a free decay (Abar = 0)"
        return super().as_dict() | {
            "model": f"{kind} along S+ by the slow flow (45) (model {self.model!r})",
            "forced": self.forced,
        }


NUISANCE = ("A0", "psi0")


class _Objective:
    """Residuals in (free parameters..., A0[, psi0]) within their ranges."""

    def __init__(self, data: TimeRecord, base: Params, names, model, forced: bool):
        self.data, self.base, self.model, self.forced = data, base, model, forced
        self.names = tuple(names) + (NUISANCE if forced else NUISANCE[:1])
        self.diff_step = 1e-6  # the integration's 1e-10 would be noise in differences of 1.5e-8
        # psi0 within two turns either side of its starts (in [-pi, pi)): the phase is periodic
        lower = {"lam": 1e-9, "chi": 1e-9, "gamma": 0.0, "Abar": 1e-9, "A0": 1e-9, "psi0": -4 * np.pi}
        self.lower = np.array([lower[n] for n in self.names])
        self.upper = np.array([4 * np.pi if n == "psi0" else np.inf for n in self.names])

    def params(self, z) -> Params:
        return self.base.replace(**{n: float(v) for n, v in zip(self.names, z) if n not in NUISANCE})

    def __call__(self, z):
        values = dict(zip(self.names, map(float, z)))
        try:
            model = record_amplitudes(
                self.params(z),
                values["A0"],
                self.data.tau,
                self.model,
                forced=self.forced,
                psi0=values.get("psi0", 0.0),
            )
        except (ValueError, RuntimeError):  # outside the admissible set: far off
            return np.full(len(self.data), 1e3 * (1.0 + float(self.data.A.max())))
        r = self.data.A - model
        return r / self.data.std if self.data.std is not None else r


def fit_time_series(
    data: TimeRecord,
    base: Params,
    free,
    *,
    forced: bool = False,
    model: str = "slowflow",
    seed: int = 0,
    progress=None,
) -> TimeSeriesFit:
    """Fit ``free`` (of :data:`DECAY_FREE`, or :data:`FORCED_FREE` for a ``forced`` record at the
    set's sigma and Abar) with A0 (and psi0) to a record; the rest from ``base``."""
    allowed, kind = (FORCED_FREE, "a forced record") if forced else (DECAY_FREE, "a free decay")
    free = free_names(free, allowed, kind)
    if model not in ("slowflow", "corrected"):
        raise ValueError(f"{kind} is fitted by the slow flows (slowflow, corrected); got {model!r}")
    if forced and base.Abar <= 0:
        raise ValueError("a forced record needs the forcing Abar > 0 it was measured at (--set Abar=...)")
    nuisance = 2 if forced else 1
    if len(data) <= len(free) + nuisance:
        raise ValueError(
            f"{data.source or 'the data'}: {len(data)} points of {kind} for {len(free) + nuisance} "
            "parameters (the free ones, A0" + (", psi0)" if forced else ")") + "; the fit needs more points"
        )
    if progress is not None:
        progress(f"{kind}: {len(data)} envelope points; least squares and profiles (tens of seconds)")
    names, note = chi_held(free, base, "The slow flow", model == "slowflow")
    objective = _Objective(data, base, names, model, forced)
    rng = np.random.default_rng(seed)
    head = [getattr(base, n) for n in names] + [float(data.A[0])]
    phases = np.linspace(-np.pi, np.pi, PHASE_STARTS, endpoint=False) if forced else [None]
    # a forced record: one start per phase (the phases are the spread); a decay: the seeded starts
    runs = [
        least_squares(
            objective, np.array(head + ([] if p is None else [p])), rng, starts=1 if forced else STARTS
        )
        for p in phases
    ]
    run = min(runs, key=lambda r: r.cost)
    r = objective(run.x)
    scale_known = data.std is not None
    misfit = misfit_of(r, scale_known)
    estimate, correlation, rank_note = wald(objective, run.x, r, scale_known, len(data))
    sentences = [note, *range_end_sentences(objective, objective.names, run.x), rank_note]
    profiles = {}
    for k, name in enumerate(objective.names):
        if name in NUISANCE:  # their Wald intervals only: the profiles cost as much again
            continue
        interval, rows, _ = profile(objective, run.x, k, misfit, scale_known, estimate[name], rng)
        estimate[name]["profile_95"] = interval
        profiles[name] = rows
        if name == "lam" and interval[0] == 0.0:
            sentences.append(ELASTIC)
    values = {n: float(v) for n, v in zip(objective.names, run.x)}
    return TimeSeriesFit(
        free,
        values,
        estimate,
        correlation,
        misfit,
        math.sqrt(float(r @ r) / len(r)),
        len(data),
        model,
        " ".join(s for s in sentences if s),
        run.status > 0,
        run.message,
        profiles,
        scale_known,
        r,
        goodness=goodness(data, r, len(objective.names), f"the slow flow ({model})"),
        forced=forced,
    )
