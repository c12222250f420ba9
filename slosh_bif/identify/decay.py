"""The wall's (and the vessel's) damping fitted to a free decay (as Fig. 9 with the forcing off):
the vessel's amplitude A(tau) falling along the slow invariant manifold (36) under the slow flow
(45) with Abar = 0, where dA/dT1 (T1 = eps tau) does not depend on the phase and carries the
impacts' loss C of (21) and the vessel's gamma; below S+'s end A_min the particle stops reaching
the walls and the vessel decays as the vessel's mode of (8)'s linear flight.

Data: a CSV with ``tau`` and ``A`` (the envelope: the vessel's amplitude at each time) or ``tau``
and ``X`` (the vessel's displacement: its envelope taken from the peaks of |X|, each refined by a
parabola through its three samples, which the leading order X = A sin(tau + psi) (25) makes A),
optional ``std``. The initial amplitude A0 at the first time is fitted with the free parameters
(a nuisance parameter); intervals and profiles as for a frequency response (:mod:`.response_stats`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np

from slosh_bif.identify.csv_table import number, read_header, read_table
from slosh_bif.identify.response_stats import least_squares, misfit_of, profile, wald
from slosh_bif.model.equations import ImpactModel
from slosh_bif.model.params import Params
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow

__all__ = ["DecayData", "DecayFit", "read_decay_data", "decay_amplitudes", "fit_decay", "DECAY_FREE"]

DECAY_FREE = ("lam", "chi", "gamma")  # and A0, always fitted


@dataclasses.dataclass(frozen=True)
class DecayData:
    """A measured free decay: times ``tau``, envelope ``A``, optional ``std``, the source file."""

    tau: np.ndarray
    A: np.ndarray
    std: np.ndarray | None = None
    source: str = ""

    def __len__(self) -> int:
        return len(self.tau)


def read_decay_data(path) -> DecayData:
    """``tau, A[, std]`` or ``tau, X`` (envelope from the peaks of |X|); one-line errors naming the
    file, line and column."""
    path = Path(path)
    signal = "X" in read_header(path) and "A" not in read_header(path)
    names = ("tau", "X") if signal else ("tau", "A")
    columns, rows = read_table(path, names, "a free decay", optional=() if signal else ("std",))
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
        return DecayData(tau, A, None, str(path))
    std = np.array(values["std"]) if "std" in values else None
    return DecayData(tau, np.array(values["A"]), std, str(path))


def envelope(tau, X) -> tuple:
    """(times, heights) of the local maxima of |X|, each the vertex of the parabola through the
    peak sample and its neighbours."""
    y = np.abs(X)
    k = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
    a, b, c = y[k - 1], y[k], y[k + 1]
    curvature = a - 2 * b + c
    shift = np.where(curvature < 0, 0.5 * (a - c) / np.where(curvature < 0, curvature, 1.0), 0.0)
    h = tau[k + 1] - tau[k]  # a uniform sample near each peak
    return tau[k] + shift * h, b - 0.25 * (a - c) * shift


def decay_amplitudes(params: Params, A0: float, tau, model: str = "slowflow") -> np.ndarray:
    """A(tau) from A0 at tau[0] with the forcing off: (45) on S+ until A_min, then the vessel's
    mode of (8)'s linear flight."""
    tau = np.asarray(tau, dtype=float)
    free = params.replace(Abar=0.0)
    T1 = free.eps * (tau - tau[0])
    out = np.empty(len(tau))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        flow = SlowFlow(free, model)
        if A0 <= flow.A_min:
            escape, A_escape = 0.0, A0
        else:
            run = flow.integrate(A0, 0.0, (0.0, float(T1[-1]) or 1e-12), t_eval=T1)
            out[: len(run.A)] = run.A
            escape, A_escape = run.T1_end, flow.A_min
    after = T1 > escape if A0 > flow.A_min else np.ones(len(tau), dtype=bool)
    if after.any():
        rate = _linear_rate(free)
        out[after] = A_escape * np.exp(-rate * (T1[after] - escape) / free.eps)
    return out


def _linear_rate(params: Params) -> float:
    """The decay rate in tau of the vessel's mode of (8)'s linear flight (no impacts): its
    eigenvalue nearest i (the particle's own mode has no stiffness at beta = 0)."""
    eigenvalues = np.linalg.eigvals(ImpactModel(params).matrix)
    return float(-eigenvalues[np.argmin(np.abs(eigenvalues - 1j))].real)


@dataclasses.dataclass(frozen=True)
class DecayFit:
    """A fitted free decay: ``values`` (the fitted parameters and A0), ``estimate`` per parameter
    (value, std, Wald and profile 95 % intervals), ``correlation``, the misfit and what the data
    do not determine."""

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
    residuals: np.ndarray

    def params(self, base: Params) -> Params:
        return base.replace(**{k: v for k, v in self.values.items() if k != "A0"})

    def as_dict(self) -> dict:
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        out.update(
            model=f"free decay along S+ by the slow flow (45) with Abar = 0 (model {self.model!r})",
            free=list(self.free),
            correlation=self.correlation.tolist(),
            residuals=self.residuals.tolist(),
            profiles={k: [list(map(float, r)) for r in v] for k, v in self.profiles.items()},
        )
        return out


class _Objective:
    """Residuals in (free parameters..., A0) within their ranges."""

    def __init__(self, data: DecayData, base: Params, names, model):
        self.data, self.base, self.model = data, base, model
        self.names = tuple(names) + ("A0",)
        self.diff_step = 1e-6  # the integration's 1e-10 would be noise in differences of 1.5e-8
        lower = {"lam": 1e-9, "chi": 1e-9, "gamma": 0.0, "A0": 1e-9}
        self.lower = np.array([lower[n] for n in self.names])
        self.upper = np.full(len(self.names), np.inf)

    def params(self, z) -> Params:
        return self.base.replace(**{n: float(v) for n, v in zip(self.names[:-1], z[:-1])})

    def __call__(self, z):
        try:
            r = self.data.A - decay_amplitudes(self.params(z), float(z[-1]), self.data.tau, self.model)
        except (ValueError, RuntimeError):  # outside the admissible set: far off
            return np.full(len(self.data), 1e3 * (1.0 + float(self.data.A.max())))
        return r / self.data.std if self.data.std is not None else r


def fit_decay(data: DecayData, base: Params, free, *, model: str = "slowflow", seed: int = 0) -> DecayFit:
    """Fit ``free`` (of :data:`DECAY_FREE`) and A0 to a free decay; the rest from ``base``."""
    free = tuple(dict.fromkeys(free))
    if not free or any(f not in DECAY_FREE for f in free):
        raise ValueError(f"--free takes one or more of {', '.join(DECAY_FREE)} for a free decay; got {free}")
    if model not in ("slowflow", "corrected"):
        raise ValueError(f"a free decay is fitted by the slow flows (slowflow, corrected); got {model!r}")
    if len(data) <= len(free) + 1:
        raise ValueError(
            f"{data.source or 'the data'}: {len(data)} decay points for {len(free) + 1} parameters "
            f"({', '.join(free)}, A0); the fit needs more points than parameters"
        )
    names, note = list(free), ""
    if model == "slowflow" and "lam" in names and "chi" in names:
        names.remove("chi")
        note = (
            "The slow flow with the law (21) depends on lam and chi only through C of (21): chi is held "
            f"at {base.chi:g} and lam fitted."
        )
    objective = _Objective(data, base, names, model)
    z0 = np.array([getattr(base, n) for n in names] + [float(data.A[0])])
    rng = np.random.default_rng(seed)
    run = least_squares(objective, z0, rng)
    r = objective(run.x)
    scale_known = data.std is not None
    misfit = misfit_of(r, scale_known)
    estimate, correlation, rank_note = wald(objective, run.x, r, scale_known, len(data))
    profiles = {}
    for k, name in enumerate(objective.names):
        interval, rows = profile(objective, run.x, k, misfit, scale_known, estimate[name], rng)
        estimate[name]["profile_95"] = interval
        profiles[name] = rows
    values = {n: float(v) for n, v in zip(objective.names, run.x)}
    return DecayFit(
        free,
        values,
        estimate,
        correlation,
        misfit,
        math.sqrt(float(r @ r) / len(r)),
        len(data),
        model,
        " ".join(s for s in (note, rank_note) if s),
        run.status > 0,
        run.message,
        profiles,
        scale_known,
        r,
    )
