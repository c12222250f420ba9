"""The wall's (and the vessel's) parameters fitted to a measured frequency response by the slow
flow's steady states (46), with standard errors, profile-likelihood intervals, correlations and a
plain statement of what the data cannot determine.

Each measured point (sigma_i, A_i) is compared with the stable steady state of (45) at sigma_i
nearest A_i (:mod:`.response_model`): an up- and a down-sweep across a hysteresis loop are two
stable branches, not one averaged curve. The residual is (A_i - A_model) / std_i (std_i = 1 when
not given; the scale is then estimated). Continuous parameters (lam, chi, gamma, Abar) are fitted
by least squares within their admissible ranges (lam down to 0, the elastic wall, a bound the fit
may reach) from several seeded starts; the integers n and pbar are profiled
(:mod:`.response_integers`). Intervals:

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

from slosh_bif.identify.assignment import UNEXPLAINED, pick, unexplained
from slosh_bif.identify.goodness import goodness
from slosh_bif.identify.response_data import ResponseData
from slosh_bif.identify.response_impact import ImpactResponse
from slosh_bif.identify.response_integers import INTEGERS, integer_estimates, integer_sets, start_at
from slosh_bif.identify.response_model import impact_free, response_curve
from slosh_bif.identify.response_orbits import LostOrbit, OrbitResponse
from slosh_bif.identify.response_result import (
    MODEL_NAMES,
    MODELS,
    ORBIT_MODELS,
    SLOW_MODELS,
    ResponseFit,
    dissipation_estimates,
)
from slosh_bif.identify.response_stats import (
    STARTS,
    least_squares,
    misfit_of,
    profile,
    spread_starts,
    wald,
)
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import dissipation_at_unit_speed
from slosh_bif.slowflow.flow import AsymptoticsWarning

REFINDS = 3  # times the orbits are chosen again at an estimate and the fit redone

__all__ = ["RESPONSE_FREE", "fit_response", "residuals", "model_amplitudes", "slow_flow_estimate"]

RESPONSE_FREE = ("lam", "chi", "gamma", "Abar", "eps", "n", "pbar")  # eps: by the orbits only
# the models where lam and chi enter only through C of (21)
C_ONLY = ("slowflow", "impact")
CONTINUOUS = ("lam", "chi", "gamma", "Abar", "eps")


def residuals(data: ResponseData, params: Params, model: str = "slowflow") -> np.ndarray:
    """(A_i - A_model_i) / std_i, A_model_i the steady state of the slow flow ``model`` point i is
    on (:func:`model_amplitudes`)."""
    out = data.A - model_amplitudes(data, params, model)
    return out / data.std if data.std is not None else out


def model_amplitudes(data: ResponseData, params: Params, model: str = "slowflow") -> np.ndarray:
    """The amplitude of the steady state each point is compared with: the candidates at its sigma
    are the steady states of (46) and the impact-free response where the particle stays inside the
    walls (:func:`~.response_model.impact_free`), and the point takes the stable one that explains
    it best, its sweep's continuing one where that explains it nearly as well
    (:func:`~.assignment.pick`). Any steady state where none is stable; 0 where there is none."""
    states = steady_states(data, params, model)
    out = np.empty(len(data))
    for i, previous in data.sweep_order():
        candidates = states[i] or [(0.0, True)]
        k = pick(data, i, None if previous is None else out[previous], candidates)
        out[i] = candidates[k][0]
    return out


def steady_states(data: ResponseData, params: Params, model: str = "slowflow") -> list:
    """(A, stable) of every steady state of the slow flow ``model`` at each point's sigma, the
    impact-free response among them where it stays inside the walls."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        # data in Hz: each point's own gamma and Abar, so its own curve
        shared = response_curve(params, model) if data.ratio is None else None
        return [_states(data, params, model, i, shared) for i in range(len(data))]


def _states(data: ResponseData, params: Params, model: str, i: int, shared) -> list:
    """(A, stable) of every steady state at point i's sigma (on the ``shared`` curve, or its own),
    the impact-free response among them where it stays inside the walls."""
    at = data.params_at(params, i)
    states = (shared or response_curve(at, model)).states_at(float(data.sigma[i]))
    A, w = impact_free(at)
    return states + [(A, True)] if w < 1.0 else states


class _Objective:
    """Residuals as a function of the continuous free parameters, each within its admissible range
    (``lower``, ``upper``): gamma >= 0, Abar > 0, eps > 0 with 1 - eps sigma > 0 at every point,
    and lam >= 0 and chi > 0 where kappa (21) stays real (C, the energy fraction lost at unit
    speed, is linear in lam and goes as chi**-a). An elastic wall, lam -> 0, is a bound the fit
    may reach, not a point at infinity."""

    def __init__(self, data, base: Params, names, model, progress=None, family=None):
        self.data, self.base, self.names, self.model = data, base, tuple(names), model
        # the full model's orbits are found once, at the base set, and followed from there (from
        # a ``family`` of (9)'s orbits already traced, when given)
        self.orbits = _orbit_response(data, base, model, progress, family)
        # an orbit's A1 is Newton's, to ~1e-12: differences of scipy's default step (1.5e-8 relative)
        # would be noise for a parameter the response hardly feels (eps)
        self.diff_step = None if self.orbits is None else 1e-6
        # (9)'s orbits carry their own parameter derivatives (the variational equations); the
        # slow flows' states and (8)'s orbits are differenced
        self.jacobian = self._jacobian if isinstance(self.orbits, OrbitResponse) else None
        self._at = None  # the z the orbits were last moved to (None: the last call lost them)
        C = float(dissipation_at_unit_speed(base.lam, base.chi, base.n, base.pbar))
        a = base.pbar / (2 * (base.n + 1)) + 0.5
        ranges = {
            "lam": (1e-9, base.lam / C * (1 - 1e-9) if C > 0 else np.inf),
            "chi": (base.chi * C ** (1 / a) * (1 + 1e-9) if C > 0 else 1e-9, np.inf),
            "gamma": (0.0, np.inf),
            "Abar": (1e-9, np.inf),
            # the vessel's stiffness 1 - eps sigma stays positive at every data point
            "eps": (
                1e-9,
                1 / sigma_top * (1 - 1e-9) if (sigma_top := float(np.max(data.sigma))) > 0 else np.inf,
            ),
        }
        self.lower = np.array([ranges[n][0] for n in self.names])
        self.upper = np.array([ranges[n][1] for n in self.names])

    def params(self, z) -> Params:
        return self.base.replace(**{n: float(v) for n, v in zip(self.names, z)})

    def save(self):
        """The orbits' state (each evaluation moves them on), for :meth:`restore`; None for the slow flows."""
        return None if self.orbits is None else self.orbits.state()

    def restore(self, state) -> None:
        if self.orbits is not None:
            self.orbits.restore(state)

    def __call__(self, z):
        self._at = None
        try:
            if self.orbits is None:
                return residuals(self.data, self.params(z), self.model)
            r = self.data.A - self.orbits.amplitudes(self.params(z))
            self._at = np.array(z, dtype=float)
            return r / self.data.std if self.data.std is not None else r
        except ValueError:  # outside the admissible set, or an orbit of (9) lost: far off
            return np.full(len(self.data), 1e3 * (1.0 + float(np.abs(self.data.A).max())))

    def _jacobian(self, z):
        """d residuals / dz from (9)'s orbits at z (moved there first unless the last call was at
        z); zero where the orbits are lost (the residual is then a constant)."""
        if self._at is None or not np.array_equal(self._at, z):
            self(z)
        if self._at is None:
            return np.zeros((len(self.data), len(self.names)))
        J = -self.orbits.gradient(self.names)
        return J / self.data.std[:, None] if self.data.std is not None else J


def fit_response(
    data: ResponseData, base: Params, free, *, model: str = "slowflow", seed: int = 0, progress=None
) -> ResponseFit:
    """Fit ``free`` (a subset of :data:`RESPONSE_FREE`) to ``data``; the rest from ``base``.
    One-line ValueErrors for a name that cannot be fitted and for fewer points than parameters.
    ``progress(message)`` is told of each stage (a fit per pbar, a profile per parameter)."""
    say = progress or (lambda message: None)
    free = tuple(dict.fromkeys(free))
    unknown = [f for f in free if f not in RESPONSE_FREE]
    if unknown or not free:
        raise ValueError(
            f"--free takes one or more of {', '.join(RESPONSE_FREE)} for a frequency response; "
            f"got {', '.join(free) or 'nothing'}"
        )
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
            f"least squares of {', '.join(continuous) or 'nothing'} at n = {n}, pbar = {pbar} from "
            f"{STARTS} starts"
        )
        objective = _Objective(data, at, continuous, model, say)
        z0 = np.array([getattr(at, name) for name in continuous], dtype=float)
        if continuous and objective.orbits is not None:
            extra = slow_flow_estimate(data, at, continuous, rng, say)
            run, objective = _orbit_starts(objective, z0, rng, say, extra)
        else:
            run = least_squares(objective, z0, rng) if continuous else None
        r = objective(run.x) if run is not None else objective(z0)
        results[n, pbar] = (misfit_of(r, scale_known), run, objective, r)
    if not results:
        raise ValueError(f"kappa (21) is not real at any n, pbar tried with lam = {base.lam:g}; free lam too")
    integers = min(results, key=lambda k: results[k][0])
    misfit, run, objective, r = results[integers]
    z = run.x if run is not None else np.zeros(0)
    fitted = objective.params(z)
    converged = run is None or run.status > 0
    message = run.message if run is not None else "no continuous parameter to fit"
    candidates = None  # the orbits found at each point near the estimate (orbit models)
    if objective.orbits is not None:
        # the orbits each point follows were chosen at the start's parameters; chosen again at the
        # estimate (:func:`~.assignment.pick`), they may be others (the start's stable set or
        # nearest orbit differed): then the fit is redone from the estimate, up to REFINDS times
        for _ in range(REFINDS):
            objective(z)  # the followed orbits at the estimate
            fresh = _Objective(data, fitted, continuous, model, say)
            candidates = fresh.orbits.candidates
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
        unstable = [f"{s:.4g}" for s, ok in zip(data.sigma, objective.orbits.stable) if not ok]
        if unstable:
            note = _join(
                note,
                f"At the estimate {MODEL_NAMES[model]} followed at sigma = {', '.join(unstable)} are "
                "unstable: a measured response cannot be them there.",
            )
    estimate, correlation, identifiability = wald(objective, z, r, scale_known, len(data))
    if identifiability:
        note = _join(note, identifiability)
    profiles = {}
    for k, name in enumerate(continuous):
        say(f"profile likelihood of {name}")
        interval, rows = profile(objective, z, k, misfit, scale_known, estimate[name], rng)
        estimate[name]["profile_95"] = interval
        profiles[name] = rows
        if name == "lam" and interval[0] == 0.0:
            note = _join(
                note, "lam's interval reaches 0: an elastic wall (kappa = 1) is consistent with the data."
            )
        for bound, side in zip(interval, ("below", "above")):
            if bound is None:
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
    if candidates is None:
        candidates = steady_states(data, fitted, model)
    fitted_count = len(continuous) + sum(name in INTEGERS for name in free)
    verdict = goodness(data, r, fitted_count, MODEL_NAMES[model])
    stable = [[float(a) for a, ok in c if ok] for c in candidates]
    bad = unexplained(data, stable, None if scale_known else verdict.noise)
    if bad:
        note = _join(
            note,
            f"No stable response of {MODEL_NAMES[model]} at the estimate explains the points at sigma = "
            f"{', '.join(f'{data.sigma[i]:.4g}' for i in bad)} (each farther than {UNEXPLAINED:g} standard "
            "deviations from every stable response there, or none there).",
        )
    model_A = data.A - (r * data.std if scale_known else r)
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
    )


def slow_flow_estimate(data, at: Params, continuous, rng, say):
    """The estimate of ``continuous`` by the slow flow (46) (eps, which does not enter it, held at
    ``at``'s), a start for an orbit fit; None where it has nothing to fit or fails. (46), not the
    corrected slow flow: the corrected one measures its wall by simulated contacts again at every
    lam or chi tried (about a second each)."""
    names = [name for name in continuous if name != "eps"]
    if not names:
        return None
    slow = _Objective(data, at, names, "slowflow")
    z0 = np.array([getattr(at, name) for name in names], dtype=float)
    try:
        run = least_squares(slow, z0, rng)
    except ValueError as err:  # a slow flow without steady states near the data
        say(f"no slow-flow start: {err}")
        return None
    fitted = slow.params(run.x)
    say(f"the slow flow's estimate as a start: {', '.join(f'{n} = {getattr(fitted, n):.4g}' for n in names)}")
    return np.array([getattr(fitted, name) for name in continuous], dtype=float)


def _orbit_starts(objective, z0, rng, say, extra=None):
    """(run, objective) of the best least squares from the base values and the base scaled by
    1/2, 2 and 1/4 (:data:`~.response_stats.ORBIT_SPREAD`), then from ``extra`` (the slow flow's
    estimate) where given, each with the orbits chosen afresh at its own parameters (which orbit
    each point follows is chosen where the fit starts, and different starts reach different
    minima: a seeded spread of a few tens of percent left the tank's fit by (8) at lam = 0,
    chi-square 276, from 0.5, and at 0.397, chi-square 109, from 0.3): all orbits stable at the end
    first, then the least misfit. A start where an orbit cannot be found is skipped."""
    best = None
    family = getattr(objective.orbits, "family", None)  # (9)'s, traced at the base, serves every start
    starts = spread_starts(z0, objective.lower, objective.upper)
    if extra is not None:
        starts.append(spread_starts(extra, objective.lower, objective.upper, factors=(1.0,))[0])
    for k, start in enumerate(starts):
        try:
            here = objective
            if k > 0:
                params = objective.params(start)
                here = _Objective(objective.data, params, objective.names, objective.model, say, family)
        except LostOrbit:
            continue
        run = least_squares(here, start, rng, starts=1)
        here(run.x)  # the orbits at the run's end
        key = (not all(here.orbits.stable), run.cost)
        if best is None or key < best[0]:
            best = (key, run, here)
    return best[1], best[2]


def _orbit_response(data, base: Params, model: str, progress, family=None):
    """The orbits each point follows, found at ``base``, for the orbit models; None for the slow flows."""
    if model == "smooth":
        return OrbitResponse(data, base, progress, family=family)
    if model in ("impact", "impact-corrected"):
        variant = "corrected" if model == "impact-corrected" else "paper"
        return ImpactResponse(data, base, progress, variant=variant)
    return None


def _join(note: str, sentence: str) -> str:
    return f"{note} {sentence}" if note else sentence
