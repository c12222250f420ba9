"""The wall's (and the vessel's) parameters fitted to a measured frequency response by the slow
flow's steady states (46), with standard errors, profile-likelihood intervals, correlations and a
plain statement of what the data cannot determine.

Each measured point (sigma_i, A_i) is compared with the stable response of the model at sigma_i
that explains it best (:mod:`.assignment`; a sweep label decides only a near tie): an up- and a
down-sweep across a hysteresis loop are two stable branches, not one averaged curve. The residual
is (A_i - A_model) / std_i (std_i = 1 when not given; the scale is then estimated). Continuous
parameters (lam, chi, gamma, Abar) are fitted by least squares within their admissible ranges (lam
down to 0, the elastic wall, a bound the fit may reach) from the given start and seeded
Latin-hypercube starts (:mod:`.response_search`: the best and the runner-up minima reported); the
integers n and pbar are profiled (:mod:`.response_integers`). Whether the fitted model describes
the data is tested (:mod:`.goodness`: the chi-square's p-value with the std given, the residuals'
structure without) and said where it does not. Intervals:

* Wald: the estimate +- 1.96 standard errors (t quantiles when the scale is estimated) from the
  Gauss-Newton covariance (J^T J)^-1 (times the residual variance when std is not given),
  clipped to the range: right for a misfit that is quadratic in the parameters;
* profile likelihood: the values where the best misfit with the parameter held rises by the
  chi-square(1) 95 % quantile 3.84 (N log RSS when the scale is estimated), the others refitted:
  right also where the misfit is not quadratic (two damping parameters trading against each
  other, a parameter at its range's end), which the coverage tests show the Wald's are not.

``model="smooth"`` compares each point with the stable 2pi-orbit of the full model (9) that it
follows (:mod:`.response_orbits`: the family traced once at the base set, each orbit then
Newton's from the last), its first-harmonic amplitude A1: the fit without the slow flow's own
error, at the cost of the family's trace (seconds to a minute) and a Newton per point and
evaluation. ``model="impact"`` does the same with the stable 2pi-orbits of the vibro-impact model
(8) (:mod:`.response_impact`; ``"impact-corrected"``: of the corrected impact model): the paper's
own model, whose difference from the slow flow's fit is the expansion's error alone.

With Newtonian restitution (pbar = 0) kappa is a constant and (46) depends on lam and chi only
through it: both free, the fit holds chi, fits lam and reports kappa with its interval. So does
(8) with the law (21) at any pbar: kappa(v)**2 = 1 - C v**q with q set by n and pbar, so lam and chi
enter only through C. eps does not enter (46) in the scaled sigma at all: it is fitted by the
orbits of (9) or (8) only.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import stats

from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.identify.assignment import UNEXPLAINED, unexplained, with_followed
from slosh_bif.identify.goodness import goodness
from slosh_bif.identify.response_data import ResponseData
from slosh_bif.identify.response_integers import INTEGERS, integer_estimates, integer_sets, start_at
from slosh_bif.identify.response_objective import Objective, model_amplitudes, residuals, steady_states
from slosh_bif.identify.response_orbits import LostOrbit
from slosh_bif.identify.response_result import (
    MODEL_NAMES,
    MODELS,
    ORBIT_MODELS,
    SLOW_MODELS,
    ResponseFit,
    dissipation_estimates,
    free_names,
)
from slosh_bif.identify.response_search import (
    ORBIT_SEARCH,
    minima_record,
    orbit_starts,
    runner_up,
    slow_flow_estimate,
)
from slosh_bif.identify.response_stats import (
    ELASTIC,
    SEARCH,
    least_squares,
    lost_sentence,
    misfit_of,
    profile_all,
    range_end_sentences,
    search_starts,
    wald,
)
from slosh_bif.model.params import Params

REFINDS = 3  # times the orbits are chosen again at an estimate and the fit redone

__all__ = [
    "RESPONSE_FREE",
    "SweepWarning",
    "fit_response",
    "residuals",
    "model_amplitudes",
    "slow_flow_estimate",
]


class SweepWarning(UserWarning):
    """A sweep label that orders nothing: a sweep of one point."""


RESPONSE_FREE = ("lam", "chi", "gamma", "Abar", "eps", "n", "pbar")  # eps: by the orbits only
# the models where lam and chi enter only through C of (21)
C_ONLY = ("slowflow", "impact")
CONTINUOUS = ("lam", "chi", "gamma", "Abar", "eps")


def fit_response(
    data: ResponseData,
    base: Params,
    free,
    *,
    model: str = "slowflow",
    seed: int = 0,
    progress=None,
    pool=None,
) -> ResponseFit:
    """Fit ``free`` (a subset of :data:`RESPONSE_FREE`) to ``data``; the rest from ``base``.
    One-line ValueErrors for a name that cannot be fitted and for fewer points than parameters.
    ``progress(message)`` is told of each stage (a fit per pbar, a profile per parameter);
    ``pool`` (an executor) runs an orbit fit's starts side by side, with the same result."""
    say = progress or (lambda message: None)
    free = free_names(free, RESPONSE_FREE, "a frequency response")
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    if "eps" in free and model in SLOW_MODELS:
        raise ValueError(
            "eps does not enter (46) in the scaled sigma: it is fitted by the orbits (--model smooth, impact)"
        )
    if "eps" in free and data.ratio is not None:
        raise ValueError(
            f"{data.source}: eps sets the map from Hz to sigma; with data in Hz it is the tank's (fit eps "
            "to a response in sigma)"
        )
    if model in ORBIT_MODELS and any(name in free for name in INTEGERS):
        raise ValueError(
            "n and pbar are profiled by the slow flows only (each value would find the orbits anew)"
        )
    continuous = [f for f in free if f in CONTINUOUS]
    if len(data) <= len(free):
        raise ValueError(
            f"{data.source or 'the data'}: {len(data)} response points for {len(free)} free parameters "
            f"({', '.join(free)}); the fit needs more points than parameters"
        )
    for direction in ("up", "down"):
        if data.sweep and data.sweep.count(direction) == 1:
            warnings.warn(
                f"{data.source or 'the data'}: the {direction}-sweep has one point only (sigma = "
                f"{data.sigma[data.sweep.index(direction)]:.4g}): a sweep label orders points along a "
                "sweep, and one point is compared with the response that explains it best",
                SweepWarning,
                stacklevel=2,
            )
    note = ""
    candidates = integer_sets(base, free)
    if not candidates:
        raise ValueError(f"no wall power n of pbar = {base.pbar}'s parity to try; free pbar too")
    if model in C_ONLY and "lam" in continuous and "chi" in continuous:
        continuous.remove("chi")
        note = (
            f"{'(46)' if model == 'slowflow' else '(8)'} with the law (21) depends on lam and chi only "
            "through the prefactor C = 1 - "
            f"kappa(1)^2 of (21): chi is held at {base.chi:g} and lam fitted; C and kappa(1) are what "
            "the response determines (reported with their intervals). A measured contact time or "
            "penetration depth (which depend on chi alone) would separate them."
        )
    scale_known = data.std is not None
    rng = np.random.default_rng(seed)
    results = {}
    for n, pbar in candidates:
        at = start_at(base, n, pbar, "lam" in continuous)
        if at is None:  # kappa not real at unit speed with this wall and lam held
            say(f"n = {n}, pbar = {pbar}: kappa (21) is not real with lam = {base.lam:g}; skipped")
            continue
        say(
            f"least squares of {', '.join(continuous) or 'nothing'} at n = {n}, pbar = {pbar}: the start and "
            f"{SEARCH} seeded Latin-hypercube starts (the best {ORBIT_SEARCH} by the slow flow for orbits)"
        )
        objective = Objective(data, at, continuous, model, say)
        z0 = np.array([getattr(at, name) for name in continuous], dtype=float)
        minima = []
        if continuous and objective.orbits is not None:
            extra = slow_flow_estimate(data, at, continuous, rng, say)
            run, objective, minima = orbit_starts(objective, z0, rng, say, extra, pool)
        elif continuous:
            # several wall powers: a few starts each, the whole search at the best (below)
            run, minima = _search(objective, z0, rng, scale_known, SEARCH if len(candidates) == 1 else 1)
        else:
            run = None
        r = objective(run.x) if run is not None else objective(z0)
        results[n, pbar] = (misfit_of(r, scale_known), run, objective, r, minima)
    if not results:
        raise ValueError(f"kappa (21) is not real at any n, pbar tried with lam = {base.lam:g}; free lam too")
    integers = min(results, key=lambda k: results[k][0])
    misfit, run, objective, r, minima = results[integers]
    if len(results) > 1 and run is not None and objective.orbits is None:  # the whole search there
        run, more = _search(objective, run.x, rng, scale_known, SEARCH)
        minima, r = minima + more, objective(run.x)
        misfit = misfit_of(r, scale_known)
        results[integers] = (misfit, run, objective, r, minima)  # the integers' profile sees it too
    second = runner_up(minima, run.x if run is not None else None)
    z = run.x if run is not None else np.zeros(0)
    fitted = objective.params(z)
    converged = run is None or run.status > 0
    message = run.message if run is not None else "no continuous parameter to fit"
    found = None  # (A1, stable) of the orbits found at each point near the estimate (orbit models)
    if objective.orbits is not None:
        # the orbits each point follows were chosen at the start's parameters; chosen again at the
        # estimate (:func:`~.assignment.pick`), they may be others (the start's stable set or
        # nearest orbit differed): then the fit is redone from the estimate, up to REFINDS times
        for _ in range(REFINDS):
            objective(z)  # the followed orbits at the estimate
            try:
                fresh = Objective(data, fitted, continuous, model, say)
            except (LostOrbit, ConvergenceError) as err:  # none found afresh: keep those followed
                note = _join(
                    note,
                    f"Orbits searched afresh at the estimate were not found ({err}); the ones "
                    "followed from the start are kept.",
                )
                found = objective.orbits.candidates
                break
            found = fresh.orbits.candidates
            r_fresh = fresh(z)
            if all(objective.orbits.stable) and misfit_of(r_fresh, scale_known) >= misfit - 1e-9 * abs(
                misfit
            ):
                break
            say(f"{MODEL_NAMES[model]}: other orbits nearer at the estimate; the fit redone from it")
            objective = fresh
            run = least_squares(objective, z, rng, starts=1)
            z, r = run.x, objective(run.x)
            misfit, fitted, converged, message = (
                misfit_of(r, scale_known),
                objective.params(run.x),
                run.status > 0,
                run.message,
            )
        objective(z)  # the orbits at the estimate (the profiles below start from them)
        followed_stable = list(objective.orbits.stable)
        unstable = [f"{s:.4g}" for s, ok in zip(data.sigma, followed_stable) if not ok]
        if unstable:
            note = _join(
                note,
                f"At the estimate {MODEL_NAMES[model]} followed at sigma = {', '.join(unstable)} are "
                "unstable: a measured response cannot be them there.",
            )
    if second is not None and second[0] - misfit <= float(stats.chi2.ppf(0.95, len(continuous))):
        where = ", ".join(f"{n} = {v:.4g}" for n, v in zip(continuous, second[1]))
        sentence = (
            f"A second minimum at {where} fits within the 95 % threshold of the best (misfit "
            f"{second[0]:.4g} against {misfit:.4g}): the data do not decide between the two."
        )
        if second[0] < misfit:  # ranked below for its orbits: the one reason a lower misfit loses
            sentence = (
                f"A minimum at {where} with a lower misfit ({second[0]:.4g} against {misfit:.4g}) was "
                "passed over: some of the orbits it follows are unstable, which a measured response "
                "cannot be; the data alone do not decide between the two."
            )
        note = _join(note, sentence)
    estimate, correlation, identifiability = wald(objective, z, r, scale_known, len(data))
    if identifiability:
        note = _join(note, identifiability)
    for sentence in range_end_sentences(objective, continuous, z):
        note = _join(note, sentence)
    profiles = {}
    outcomes = profile_all(
        objective, z, list(enumerate(continuous)), misfit, scale_known, estimate, rng, pool=pool, say=say
    )
    for name, (interval, rows, lost) in zip(continuous, outcomes):
        estimate[name]["profile_95"] = interval
        profiles[name] = rows
        if name == "lam" and interval[0] == 0.0:
            note = _join(note, ELASTIC)
        for sentence in lost_sentence(name, lost):
            note = _join(note, sentence)
        lost_sides = {"below" if side < 0 else "above" for side, _ in lost}
        for bound, side in zip(interval, ("below", "above")):
            if bound is None and side not in lost_sides:
                reached = min(v for v, _ in rows) if side == "below" else max(v for v, _ in rows)
                note = _join(
                    note,
                    f"The data do not bound {name} from {side}: its profile stays within 3.84 of the "
                    f"best out to {name} = {reached:.4g}.",
                )
    integer_estimate, integer_values, sentences = integer_estimates(
        free, {k: v[0] for k, v in results.items()}, integers
    )
    estimate.update(integer_estimate)
    for sentence in sentences:
        note = _join(note, sentence)
    if "lam" in continuous and "chi" in free and "chi" not in continuous:
        estimate.update(dissipation_estimates(fitted, estimate["lam"]))
    values = {name: float(getattr(fitted, name)) for name in continuous} | integer_values
    rms = math.sqrt(float(r @ r) / len(r))
    fitted = fitted.replace(**integer_values)
    if found is None:
        found = steady_states(data, fitted, model)
    fitted_count = len(continuous) + sum(name in INTEGERS for name in free)
    verdict = goodness(data, r, fitted_count, MODEL_NAMES[model])
    stable = [[float(a) for a, ok in c if ok] for c in found]
    model_A = data.A - (r * data.std if scale_known else r)
    if objective.orbits is not None:
        stable = with_followed(stable, model_A, followed_stable)
    bad = unexplained(data, stable, None if scale_known else verdict.noise)
    if bad:
        note = _join(
            note,
            f"No stable response of {MODEL_NAMES[model]} at the estimate explains the points at sigma = "
            f"{', '.join(f'{data.sigma[i]:.4g}' for i in bad)} (each farther than {UNEXPLAINED:g} standard "
            "deviations from every stable response there, or none there).",
        )
    assignment = [
        {
            "sigma": float(data.sigma[i]),
            "A": float(data.A[i]),
            "sweep": data.sweep[i] if data.sweep else "",
            "model_A": float(model_A[i]),
            "stable_candidates": stable[i],
            "explained": i not in bad,
        }
        for i in range(len(data))
    ]
    return ResponseFit(
        free,
        values,
        estimate,
        correlation,
        misfit,
        rms,
        len(data),
        model,
        note,
        converged,
        message,
        profiles,
        scale_known,
        r,
        verdict,
        assignment,
        minima_record(continuous, misfit, z, second),
    )


def _search(objective, z0, rng, scale_known, count):
    """(best run, minima) of least squares from ``z0`` and ``count`` seeded Latin-hypercube starts."""
    starts = [z0] + search_starts(z0, objective.lower, objective.upper, rng, count=count)
    runs = [least_squares(objective, start, rng, starts=1) for start in starts]
    return min(runs, key=lambda each: each.cost), [
        (misfit_of(each.fun, scale_known), each.x) for each in runs
    ]


def _join(note: str, sentence: str) -> str:
    return f"{note} {sentence}" if note else sentence
