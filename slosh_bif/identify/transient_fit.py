"""The wall's and the vessel's parameters fitted to a record from a known start (a free decay, or a
forced transient) by the trajectory of the smooth model (9) or the vibro-impact model (8) itself
(:mod:`.transient_record`), the vessel's start X0 fitted with them.

A transient of an impacting oscillator is predictable only for a while: the impacts, timed against
the vessel's motion, amplify any change of the parameters (the Fig. 10 decay's sensitivity dX/dlam
grows from 5 by tau = 30 to 1e6 by tau = 100), so the misfit over a long record is a landscape of
narrow valleys that a least squares from 10 % off does not reach the right one of. The fit
therefore grows its window: the first :data:`WINDOW` time units first, then each window longer by
as much, each fitted from the last window's estimate (a continuation in the record's length: the
last estimate lies in the new window's valley). It stops at the first window the model, refitted,
does not describe (the goodness of fit at p < 0.001, :mod:`.goodness`; with the std given and the
refit's valley quadratic, the model is then said not to describe the record), or, once a window's misfit
has been quadratic within one standard error (its rise there within a factor :data:`QUADRATIC` of
1 for every parameter), at the first window where it no longer is: the **horizon**, beyond which
the record tells its statistics (the slow flow's envelope, :mod:`.time_series`), not its
trajectory, and the intervals would be read off a landscape of narrow valleys. Wald and profile
intervals are those of the record up to the horizon, the profiles scanned across the misfit's
valleys (:mod:`.profile_scan`); their goodness of fit passes there by the horizon's choice, so
what ended the windows is reported beside them. The misfit has narrow valleys side by side: each
window follows a few (:mod:`.transient_valleys`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.identify.goodness import THRESHOLD, goodness
from slosh_bif.identify.profile_scan import LinearValley, scanned_profile
from slosh_bif.identify.response_objective import admissible_ranges
from slosh_bif.identify.response_result import ResponseFit, chi_held, free_names
from slosh_bif.identify.response_stats import interval_statistics, misfit_of, wald
from slosh_bif.identify.transient_record import (
    TRAJECTORY_NAMES,
    TRANSIENT_MODELS,
    Trajectory,
    TransientRecord,
)
from slosh_bif.identify.transient_valleys import (
    at_range_end,
    best_valley,
    followed,
    span_valleys,
)
from slosh_bif.model.params import Params

__all__ = ["TRANSIENT_FREE", "WINDOW", "TransientFit", "fit_transient"]

TRANSIENT_FREE = ("lam", "chi", "gamma", "eps", "Abar")  # Abar forced only; X0 always fitted
WINDOW = 5.0  # the first window's length and each window's growth, in tau (under a vessel period)
QUADRATIC = 2.0  # the misfit's rise at one standard error within this factor of 1: quadratic


@dataclasses.dataclass(frozen=True)
class TransientFit(ResponseFit):
    """A fitted record from a known start: as a :class:`~.response_result.ResponseFit` (``values``
    also holding X0, the nuisance start), with the ``horizon`` (the last time fitted), the
    ``windows`` tried (end, samples, misfit, p-value, curvature factor), the fitted
    ``trajectory`` over the record (tau, X; beyond the horizon a prediction) and whether the
    record is ``forced``."""

    horizon: float = math.nan
    windows: list = dataclasses.field(default_factory=list)
    trajectory: dict = dataclasses.field(default_factory=dict)
    forced: bool = False

    def params(self, base: Params) -> Params:
        return base.replace(**{k: v for k, v in self.values.items() if k != "X0"})

    def as_dict(self) -> dict:
        kind = "a forced transient" if self.forced else "a free decay (Abar = 0)"
        return super().as_dict() | {
            "model": f"{kind} from rest by {TRAJECTORY_NAMES[self.model]} (model {self.model!r})",
            "record": "forced" if self.forced else "decay",
            "horizon": self.horizon,
            "windows": self.windows,
            "trajectory": self.trajectory,
        }


class _Objective:
    """The head of a record's residuals (X_k - X(tau_k)) / std_k in (free parameters..., X0)."""

    def __init__(self, record: TransientRecord, base: Params, names, model: str):
        self.record, self.base = record, base
        self.names = tuple(names) + ("X0",)
        self.trajectory = Trajectory(model)
        self.jacobian = self._jacobian if self.trajectory.differentiates(names) else None
        self.diff_step = 1e-6
        self.valley = None  # set at the estimate: where a profile's refits start
        ranges = admissible_ranges(base, base.sigma) | {"X0": (-1e9, 1e9)}  # finite: the starts sit inside
        self.lower = np.array([ranges[n][0] for n in self.names])
        self.upper = np.array([ranges[n][1] for n in self.names])

    def params(self, z) -> Params:
        return self.base.replace(**{n: float(v) for n, v in zip(self.names[:-1], z[:-1])})

    def __call__(self, z):
        try:
            X = self.trajectory.values(self.params(z), float(z[-1]), self.record.tau)
        except (ValueError, RuntimeError):  # outside the admissible set, or a run that fails: far off
            return np.full(len(self.record), 1e3 * (1.0 + float(np.abs(self.record.X).max())))
        r = self.record.X - X
        return r / self.record.std if self.record.std is not None else r

    def profile(self, z, k, best, scale_known, estimate, rng):
        """The profile of parameter k scanned across the misfit's valleys (:mod:`.profile_scan`)."""
        return scanned_profile(self, z, k, best, scale_known, estimate, self.valley)

    def _jacobian(self, z):
        try:
            dX = self.trajectory.derivatives(self.params(z), float(z[-1]), self.record.tau, self.names[:-1])[
                1
            ]
        except (ValueError, RuntimeError):
            return np.zeros((len(self.record), len(self.names)))
        return -dX / self.record.std[:, None] if self.record.std is not None else -dX


def fit_transient(
    record: TransientRecord,
    base: Params,
    free,
    *,
    model: str = "smooth",
    forced: bool = False,
    window: float = WINDOW,
    progress=None,
    pool=None,
    seed: int = 0,
) -> TransientFit:
    """Fit ``free`` (of :data:`TRANSIENT_FREE`; Abar only ``forced``) and X0 to ``record`` by the
    trajectory of ``model`` from rest, the window grown by ``window`` up to the horizon; the rest
    from ``base`` (a free decay at Abar = 0; ``forced``: at the set's sigma and Abar). ``pool``:
    the search for other valleys and the profiles side by side; ``seed``: the search's starts."""
    say = progress or (lambda message: None)
    allowed = TRANSIENT_FREE if forced else tuple(n for n in TRANSIENT_FREE if n != "Abar")
    free = free_names(free, allowed, f"a {'forced' if forced else 'decay'} record by the full model")
    if model not in TRANSIENT_MODELS:
        raise ValueError(f"a record from rest is fitted by {', '.join(TRANSIENT_MODELS)}; got {model!r}")
    if forced and base.Abar <= 0:
        raise ValueError("a forced transient needs the forcing Abar > 0 it was measured at (--set Abar=...)")
    if not (math.isfinite(window) and window > 0):
        raise ValueError(f"the window's growth must be a positive number of time units; got {window}")
    if len(record) <= len(free) + 1:
        raise ValueError(
            f"{record.source or 'the record'}: {len(record)} samples for {len(free)} free parameters and X0"
        )
    base = base if forced else base.replace(Abar=0.0)
    names, note = chi_held(free, base, "(8)", model == "impact")
    search = np.random.default_rng(seed)
    start = np.array([getattr(base, n) for n in names] + [float(record.X[0])])
    fitted, windows, quadratic, valleys, tracked = None, [], False, [start], []
    ends = np.arange(record.tau[0] + window, record.tau[-1], window).tolist() + [float(record.tau[-1])]
    for end in ends:
        count = int(np.searchsorted(record.tau, end, side="right"))
        if count <= len(names) + 2:
            continue
        objective = _Objective(record.head(count), base, names, model)
        runs = followed(objective, valleys, search, pool)
        run = runs[0]
        r = objective(run.x)
        verdict = goodness(objective.record, r, len(names) + 1, TRAJECTORY_NAMES[model])
        curvature = _curvature(objective, run.x, r)
        windows.append([float(end), count, misfit_of(r, record.std is not None), verdict.p_value, curvature])
        say(
            f"{TRAJECTORY_NAMES[model]}: the record to tau = {end:.4g} ({count} samples), p = "
            f"{verdict.p_value:.2g}"
        )
        rejected = record.std is not None and not verdict.describes  # without a std: the runs' test
        if fitted is not None and (rejected or (quadratic and curvature > QUADRATIC)):
            break
        fitted, tracked = (objective, run, r, verdict, end), runs[1:]
        inside = [o.x for o in runs if not at_range_end(objective, o.x)]
        if end < ends[-1] and not inside:  # too short to say: the next from here
            continue
        valleys = inside or [run.x]
        quadratic = quadratic or curvature <= QUADRATIC
        if rejected:  # the first window already: the misfit is said
            break
    if fitted is None:
        raise ValueError(
            f"{record.source or 'the record'}: too few samples in its first {window:g} time units"
        )
    say(f"{TRAJECTORY_NAMES[model]}: other valleys of the misfit up to tau = {fitted[4]:.4g}")
    z, fitted, minima = best_valley(fitted[1].x, fitted, model, search, pool, tracked)
    return _result(record, (free, names, model, forced, note), z, fitted, windows, (say, pool, minima))


def _curvature(objective: _Objective, z, r) -> float:
    """How far the misfit is from its quadratic model at one standard error: for each parameter,
    the misfit's rise one Wald standard error either side along its profile's linear direction
    (the covariance's column: the others moving as the linear fit would move them), averaged over
    the two sides (their odd terms cancel), is 1 where the residuals are linear; the largest
    factor by which any differs from 1 (inf where a side leaves the admissible set)."""
    points = len(r)
    scale_known = objective.record.std is not None
    estimate, correlation, _ = wald(objective, z, r, scale_known, points)
    sd = np.array([estimate[n]["std"] for n in objective.names])
    if not np.all(np.isfinite(sd)) or np.any(sd <= 0):
        return math.inf
    cov = correlation * np.outer(sd, sd)
    s2 = 1.0 if scale_known else float(r @ r) / max(points - len(z), 1)
    worst = 1.0
    for k in range(len(z)):
        step = cov[:, k] / sd[k]
        rises = []
        for sign in (1.0, -1.0):
            moved = np.asarray(z) + sign * step
            if np.any(moved < objective.lower) or np.any(moved > objective.upper):
                return math.inf
            rr = objective(moved)
            rises.append((float(rr @ rr) - float(r @ r)) / s2)
        mean = 0.5 * sum(rises)
        if mean <= 0:
            return math.inf
        worst = max(worst, mean, 1.0 / mean)
    return float(worst)


def _valley(objective: _Objective, z, r) -> LinearValley:
    """Where the linear fit at ``z`` puts the other parameters with one held: a profile's refits
    start there (the valley is too narrow to follow from the last)."""
    estimate, correlation, _ = wald(objective, z, r, objective.record.std is not None, len(r))
    sd = np.array([estimate[n]["std"] for n in objective.names])
    return LinearValley(
        np.array(z, dtype=float), correlation * np.outer(sd, sd), objective.lower, objective.upper
    )


def _result(record, what, z, fitted, windows, tell) -> TransientFit:
    free, names, model, forced, note = what
    say, pool, minima = tell
    objective, run, r, verdict, horizon = fitted
    scale_known = record.std is not None
    sentences = [note] if note else []
    beyond = len(record) - len(objective.record)
    if beyond:
        end, count, chi2, p_next, curvature = windows[-1]
        misfit = end > horizon and p_next < THRESHOLD and scale_known and curvature <= QUADRATIC
        why = (
            "the model does not describe the first window"
            if end <= horizon
            else "refitted to the next window, the misfit is no longer quadratic within one standard error "
            f"(its rise there off by a factor {curvature:.3g}): the trajectory hangs on the parameters' "
            "last digits and no interval could be read from it"
            if not misfit
            else "the model refitted to the next window does not describe it"
        )
        if misfit:  # a valley the refit found, quadratic, whose floor is too high: the model, not chaos
            verdict = dataclasses.replace(
                verdict,
                describes=False,
                statement=f"{TRAJECTORY_NAMES[model]} as fitted does not describe the record past tau = "
                f"{horizon:.4g}: refitted to tau = {end:.4g} it leaves chi-square {chi2:.4g} for "
                f"{count - len(names) - 1} degrees of freedom (p = {p_next:.2g})",
            )
        sentences.append(
            f"Fitted up to the horizon tau = {horizon:.4g} ({len(objective.record)} samples); the {beyond} "
            f"samples after it are not: {why}. A transient with impacts is chaotic; beyond its horizon "
            "the record tells its statistics, not its trajectory (the slow flow's envelope fits the "
            "whole record: --model slowflow)."
        )
    objective.valley = _valley(objective, z, r)
    estimate, correlation, profiles, said = interval_statistics(
        objective, z, r, scale_known, len(r), np.random.default_rng(0), names, pool=pool, say=say
    )
    sentences += said + span_valleys(estimate, names, z, minima, misfit_of(r, scale_known))
    try:
        whole = Trajectory(model).values(objective.params(z), float(z[-1]), record.tau)
    except RuntimeError:
        whole = np.full(len(record), np.nan)
    return TransientFit(
        free,
        {n: float(v) for n, v in zip(objective.names, z)},
        estimate,
        correlation,
        misfit_of(r, scale_known),
        math.sqrt(float(r @ r) / len(r)),
        len(r),
        model,
        " ".join(sentences),
        run.status > 0,
        run.message,
        profiles,
        scale_known,
        r,
        goodness=verdict,
        horizon=float(horizon),
        windows=windows,
        trajectory={
            "tau": record.tau.tolist(),
            "X": [None if not math.isfinite(x) else float(x) for x in whole],
        },
        forced=forced,
    )
