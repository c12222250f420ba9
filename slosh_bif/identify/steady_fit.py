"""The wall's and the vessel's parameters fitted to a settled forced record in time X(tau) by the
2pi-orbit of the full model it follows: of the smooth model (9) or of the vibro-impact model (8)
(:mod:`.steady_record`). Each sample is compared with the orbit at the sample's phase, so the
record's whole shape speaks (the harmonics the impacts put in it), not its amplitude alone; eps
enters, as it does the orbits of (9) and (8). Records at several forcing frequencies (a file with a
sigma column) are fitted together, each sample by its own frequency's orbit.

The least squares runs within the parameters' admissible ranges
(:func:`~.response_objective.admissible_ranges`) from the given values and from them scaled by
:data:`SPREAD`, each start choosing its orbit afresh (different orbits are different minima); at
the estimate the orbit is chosen again and the fit redone where another explains the record
better. Wald and profile-likelihood intervals, correlations, the runner-up minimum and the
goodness of fit (chi-square with the std given, runs of one sign along time without) as for a
frequency response (:mod:`.response_stats`, :mod:`.goodness`). With the law (21) in (8), lam and
chi enter only through C: both free, chi is held.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
from scipy import stats

from slosh_bif.identify.goodness import goodness
from slosh_bif.identify.response_objective import admissible_ranges
from slosh_bif.identify.response_orbits import LostOrbit
from slosh_bif.identify.response_result import MODEL_NAMES, ORBIT_MODELS, ResponseFit, chi_held, free_names
from slosh_bif.identify.response_search import minima_record, runner_up
from slosh_bif.identify.response_stats import interval_statistics, least_squares, misfit_of, spread_starts
from slosh_bif.identify.steady_record import RecordOrbits, SteadyRecord
from slosh_bif.model.params import Params
from slosh_bif.slowflow.flow import AsymptoticsWarning

__all__ = ["STEADY_FREE", "SPREAD", "SteadyFit", "fit_steady_record", "refine_start"]

STEADY_FREE = ("lam", "chi", "gamma", "Abar", "eps")
SPREAD = (1.0, 0.6, 1.6)  # the starts: the given values scaled by these
REFINDS = 2  # times the orbit is chosen again at an estimate and the fit redone
CURVE = 256  # phases of the fitted orbit kept in fit.json


@dataclasses.dataclass(frozen=True)
class SteadyFit(ResponseFit):
    """A fitted settled record: as a :class:`~.response_result.ResponseFit`, with the ``orbits``
    at the estimate over one period (each record's: sigma, phases, X, stable), whether all are
    ``stable`` and the ``candidates`` (sigma, A1, stable) among which each was chosen."""

    orbits: list = dataclasses.field(default_factory=list)
    stable: bool = True
    candidates: list = dataclasses.field(default_factory=list)

    def as_dict(self) -> dict:
        return super().as_dict() | {
            "model": f"a settled forced record by {MODEL_NAMES[self.model]} (model {self.model!r})",
            "record": "steady",
            "orbits": self.orbits,
            "orbit_stable": self.stable,
            "candidates": [list(c) for c in self.candidates],
        }


class _Objective:
    """The record's residuals (X_k - X(tau_k)) / std_k in the free parameters, within their ranges."""

    def __init__(self, record: SteadyRecord, base: Params, names, model: str, progress=None):
        self.record, self.base, self.names, self.model = record, base, tuple(names), model
        self.orbit = RecordOrbits(record, base, model, progress)
        self.diff_step = 1e-6
        self.jacobian = self._jacobian if self.orbit.differentiates(self.names) else None
        self.lower, self.upper = _bounds(base, self.names, max(self.orbit.sigmas))
        self._at = None  # the z the orbit was last moved to (None: the last call lost it)
        self.lost = False  # whether the last call lost the orbit (or left the admissible set)

    def params(self, z) -> Params:
        return self.base.replace(**{n: float(v) for n, v in zip(self.names, z)})

    def save(self):
        return self.orbit.state()

    def restore(self, state) -> None:
        self.orbit.restore(state)

    def __call__(self, z):
        self._at, self.lost = None, True
        try:
            X = self.orbit.samples(self.params(z))
        except (ValueError, RuntimeError):  # outside the admissible set, or the orbit lost: far off
            return np.full(len(self.record), 1e3 * (1.0 + float(np.abs(self.record.X).max())))
        self._at, self.lost = np.array(z, dtype=float), False
        r = self.record.X - X
        return r / self.record.std if self.record.std is not None else r

    def _jacobian(self, z):
        """d residuals / dz from the orbit's sensitivities at z; zero where the orbit is lost."""
        if self._at is None or not np.array_equal(self._at, z):
            self(z)
        if self._at is None:
            return np.zeros((len(self.record), len(self.names)))
        try:
            J = -self.orbit.gradient(self.names)
        except LostOrbit:  # at a fold: no derivative
            return np.zeros((len(self.record), len(self.names)))
        return J / self.record.std[:, None] if self.record.std is not None else J


def _bounds(base: Params, names, sigma_top: float) -> tuple:
    ranges = admissible_ranges(base, sigma_top)
    return np.array([ranges[n][0] for n in names]), np.array([ranges[n][1] for n in names])


def fit_steady_record(
    record: SteadyRecord,
    base: Params,
    free,
    *,
    model: str = "smooth",
    seed: int = 0,
    progress=None,
    pool=None,
) -> SteadyFit:
    """Fit ``free`` (of :data:`STEADY_FREE`) to a settled ``record`` at ``base``'s sigma and Abar
    by the orbits of ``model`` (smooth, impact, impact-corrected); the rest from ``base``.
    ``pool`` (an executor): the starts and the profiles side by side, with the same result."""
    say = progress or (lambda message: None)
    free = free_names(free, STEADY_FREE, "a settled record")
    if model not in ORBIT_MODELS:
        raise ValueError(
            f"a settled record is fitted by the orbits ({', '.join(ORBIT_MODELS)}); got {model!r}"
        )
    if base.Abar <= 0:
        raise ValueError(
            "a settled forced record needs the forcing Abar > 0 it was measured at (--set Abar=...)"
        )
    if len(record) <= len(free):
        raise ValueError(
            f"{record.source or 'the record'}: {len(record)} samples for {len(free)} free parameters; "
            "the fit needs more samples than parameters"
        )
    names, note = chi_held(free, base, "(8)", model == "impact")
    scale_known = record.std is not None
    rng = np.random.default_rng(seed)
    z0 = np.array([getattr(base, n) for n in names], dtype=float)
    lower, upper = _bounds(base, names, max(sigma for sigma, _ in record.parts(base.sigma)))
    best, minima = None, []
    starts = spread_starts(z0, lower, upper, factors=SPREAD)
    say(f"{MODEL_NAMES[model]}: least squares from {'; '.join(_show(names, start) for start in starts)}")
    if pool is None:
        outcomes = [refine_start(record, base, names, model, start) for start in starts]
    else:
        futures = [pool.submit(refine_start, record, base, names, model, start) for start in starts]
        outcomes = [future.result() for future in futures]
    for outcome in outcomes:
        if outcome is None:  # no orbit to follow from that start
            continue
        run, objective = outcome
        minima.append((misfit_of(run.fun, scale_known), run.x))
        key = (not objective.orbit.stable, run.cost)
        if best is None or key < best[0]:
            best = (key, run, objective)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        if best is None:
            raise LostOrbit(
                f"none of {MODEL_NAMES[model]} found to follow at {_at(record, base)} from "
                "any start (the response there may not be periodic; fit by another model)"
            )
        _, run, objective = best
        z, r = run.x, objective(run.x)
        misfit = misfit_of(r, scale_known)
        for _ in range(REFINDS):  # the orbit chosen again at the estimate
            try:
                fresh = _Objective(record, objective.params(z), names, model)
            except (LostOrbit, ValueError, RuntimeError):
                break
            if objective.orbit.stable and misfit_of(fresh(z), scale_known) >= misfit - 1e-9 * abs(misfit):
                break
            say(f"{MODEL_NAMES[model]}: another orbit nearer at the estimate; the fit redone from it")
            objective, run = fresh, least_squares(fresh, z, rng, starts=1)
            z, r = run.x, fresh(run.x)
            misfit = misfit_of(r, scale_known)
        return _result(
            record, (free, names, model, note), (run, objective, z, r, misfit), minima, rng, (say, pool)
        )


def refine_start(record: SteadyRecord, base: Params, names, model: str, start):
    """(run, objective at its end) of the least squares from ``start``, the orbit chosen afresh at
    the start's parameters; None where no orbit is found there."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        try:
            objective = _Objective(record, base.replace(**dict(zip(names, start))), names, model)
        except (LostOrbit, ValueError, RuntimeError):
            return None
        run = least_squares(objective, start, np.random.default_rng(0), starts=1)  # one start: no draw
        objective(run.x)  # the orbit at the run's end
    return run, objective


def _result(record, what, best, minima, rng, tell) -> SteadyFit:
    """The estimate's statistics: Wald, profiles, the runner-up, goodness, the orbit (``what``: the
    free names, those fitted, the model and the note so far; ``tell``: progress and pool)."""
    free, names, model, note = what
    say, pool = tell
    run, objective, z, r, misfit = best
    scale_known = record.std is not None
    sentences = [note] if note else []
    if not objective.orbit.stable:
        where = ", ".join(f"{sigma:g}" for sigma in objective.orbit.unstable)
        sentences.append(
            f"At the estimate the orbit of {MODEL_NAMES[model]} followed at sigma = {where} is unstable: a "
            "settled record cannot be it."
        )
    second = runner_up(minima, z)
    if second is not None and second[0] - misfit <= float(stats.chi2.ppf(0.95, len(names))):
        sentences.append(
            f"A second minimum at {_show(names, second[1])} fits within the 95 % threshold of the best "
            f"(misfit {second[0]:.4g} against {misfit:.4g}): the record does not decide between the two."
        )
    estimate, correlation, profiles, said = interval_statistics(
        objective, z, r, scale_known, len(record), rng, names, pool=pool, say=say
    )
    sentences += said
    objective(z)  # the orbit back at the estimate
    return SteadyFit(
        free,
        {n: float(v) for n, v in zip(names, z)},
        estimate,
        correlation,
        misfit,
        math.sqrt(float(r @ r) / len(r)),
        len(record),
        model,
        " ".join(sentences),
        run.status > 0,
        run.message,
        profiles,
        scale_known,
        r,
        goodness=_verdict(goodness(record, r, len(names), MODEL_NAMES[model]), objective.orbit.stable, model),
        minima=minima_record(names, misfit, z, second),
        orbits=objective.orbit.curves(np.linspace(0.0, 2 * np.pi, CURVE + 1)),
        stable=objective.orbit.stable,
        candidates=objective.orbit.candidates,
    )


def _verdict(verdict, stable: bool, model: str):
    """The goodness of fit, and where the fitted orbit is unstable, that it does not describe a
    settled record whatever its misfit."""
    if stable:
        return verdict
    statement = (
        f"{MODEL_NAMES[model]} as fitted does not describe a settled record: the orbit at the estimate is "
        f"unstable (p = {verdict.p_value:.2g} for its misfit alone)"
    )
    return dataclasses.replace(verdict, describes=False, statement=statement)


def _at(record: SteadyRecord, base: Params) -> str:
    """Where the record was measured: its sigma, or each of its sigmas."""
    return "sigma = " + ", ".join(f"{sigma:.6g}" for sigma, _ in record.parts(base.sigma))


def _show(names, z) -> str:
    return ", ".join(f"{n} = {v:.4g}" for n, v in zip(names, z))
