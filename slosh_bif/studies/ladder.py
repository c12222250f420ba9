"""The lightest model that answers a question ("model no more than a scene needs").

:func:`answer` takes a question, a parameter set and a tolerance, picks the cheapest model whose
error, as measured by ``python -m benchmarks`` (``docs/bench``) and the regime map of ``docs/regimes_fig13``,
stays within the tolerance for those parameters, runs it and says which model it used, why, and
its error estimate.

Cost order, measured (``docs/bench``, one run): the slow flow (eq. 46 continuation 0.02 s a
curve; (45) integrated 0.1 s) < the impact model (8) simulated by its compiled exact flow (about
0.01 s / 100 periods on the Fig. 10 set) < the smooth model (9) simulated with the compiled
integrator (0.036 s / 100 periods at n = 50); shooting on (9) costs a settling simulation plus
Newton (0.15-0.2 s a point). The orbits of the impact model (8) (a branch of its exact map, 1-2 s)
are the frequency response's rung between the slow flows and shooting on (9): their error as an
answer is the rigid wall's, (8) against (9), over the stable states where both have a stable
orbit: largest 0.48 at n = 20 and 0.16 at n = 50 (``trust --impact`` on the Fig. 13 set; on the
Fig. 10 set, ``compare --impact``, 0.099 at n = 50): (8)'s first-order coefficients and its wall
together. The orbits of the corrected impact model ((9) with its wall's own law, about twice (8)'s
cost) are the next rung: their error is the contact's duration alone (``trust --impact
--impact-model corrected``, the same states). For the other questions the impact models' errors
are not measured per question, and they are not on their ladders.

Error of the slow flow, measured where the asymptotics are in range (``asymptotics_concerns``
empty): amplitude of X, largest relative error over the sigmas of ``bench.FR_SIGMAS`` against
shooting on (9): 0.28 (Fig. 10 set; 0.283 with continuation steps of 0.5), 0.20 (Fig. 13 set); critical
forcing Abar_b
of (46) against Abar_c of (9) (the least forcing with stable period-1 orbits with wall contact,
over every family at that sigma): 0.02-0.37 (``critical_forcing.csv``: 2-7 % at sigma = -6,
-1.2, 0.7 (Fig. 10 set) and 0.5, 1 (Fig. 13 set), 13-16 % below the resonance on the Fig. 13
set, 20-37 % at sigma = 4 and 6 on the Fig. 10 set, where (9)'s resonant orbit is unstable to a
torus well above Abar_b); regime
(resonant or not, slow flow (45) integrated from the initial state vs the smooth model's
classification on the 17 x 13 map of the Fig. 13 set): 172 of 221 agree, 22 % wrong. Outside
the checked range the slow flow's error is unknown and it is not used.

The corrected slow flow (kappa and clearance of the wall itself, ``model="corrected"``) is the
rung between (46) and shooting, for the frequency response and the critical forcing (the two
questions its error was measured on, ``docs/bench``: same sigmas, same references): 0.25 and 0.35
(Fig. 10 set, where the critical forcing at sigma = 4, 6 is a torus bifurcation no slow flow sees;
on the Fig. 13 set alone 0.10 and 0.038, against (46)'s 0.20 and 0.16). It costs 1.7-2.4 times
(46) (0.08-0.25 s a curve in the bench, plus 1-3 s once per wall to measure it) and is used where
(46) is out of its range or its error exceeds the tolerance, and the corrected model is in its own
range: the wall's dissipation is no concern of it, but n < 10 is (the trust maps: at n = 6 it is
within 1.6-6.6 % of (9) at the Fig. 10 set's forcing with eps <= 0.05, but 11-55 % at the Fig. 13
set's weaker forcing).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.model.presets import CLASSIFY_TMAX, get_preset
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.impact.branches import trace_impact_orbits
from slosh_bif.orbits.impact.starts import impact_start
from slosh_bif.orbits.settings import NO_SWITCHING, ParameterRange
from slosh_bif.orbits.starts import settle_and_shoot, slow_flow_start
from slosh_bif.simulation.direct import simulate
from slosh_bif.simulation.regimes import classify
from slosh_bif.slowflow.critical import critical_forcing
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow, asymptotics_concerns
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies.chart.critical import critical_forcing_full

__all__ = [
    "QUESTIONS",
    "SLOW_FLOW_ERROR",
    "CORRECTED_ERROR",
    "IMPACT_ERROR",
    "Answer",
    "answer",
    "model_choice",
]

QUESTIONS = ("frequency-response", "critical-forcing", "time-response", "regime")

# Largest measured error of the slow flow per question, inside the checked range (see above).
SLOW_FLOW_ERROR = {
    "frequency-response": 0.29,
    "critical-forcing": 0.38,
    "time-response": 0.29,
    "regime": 0.22,
}
# The same for the corrected slow flow (``docs/bench``: frequency_response.csv, critical_forcing.csv).
CORRECTED_ERROR = {"frequency-response": 0.26, "critical-forcing": 0.36}
SLOW_FLOW, CORRECTED = "slow flow", "corrected slow flow"
IMPACT = "impact model (8): its periodic orbits"
# The largest wall error of the orbits of (8) against those of (9), (8)'s own error as an answer,
# per wall exponent n: ``trust --impact`` on the Fig. 13 set (docs/trust/fig13-impact, the stable
# states of (46) with a stable orbit of both nearby). Used from the largest measured n at or below
# the set's (the error falls as n grows); below the least n measured, not at all.
IMPACT_ERROR = {"frequency-response": {20: 0.49, 50: 0.16}}
CORRECTED_IMPACT = "corrected impact model: its periodic orbits"
# The same for the corrected impact model ((9) with its wall's own law; its error is the contact's
# duration alone): ``trust --impact --impact-model corrected`` on the Fig. 13 set
# (docs/trust/fig13-impact-corrected). It costs about twice (8)'s flow, far below shooting on (9).
CORRECTED_IMPACT_ERROR = {"frequency-response": {20: 0.031, 50: 0.014}}
_IMPACT_RUNGS = (  # (model, its error per n, its name in a reason, ImpactFlow's variant)
    (IMPACT, IMPACT_ERROR, "(8)", "paper"),
    (CORRECTED_IMPACT, CORRECTED_IMPACT_ERROR, "the corrected impact model", "corrected"),
)
# Error of the full-model answers. Measured: shooting at rtol 1e-10 is within 2e-8 of the rtol
# 1e-12 reference (frequency_response.csv). Not measured, stated: the critical forcing is a special
# point located on a branch continued at rtol 1e-10 (1e-6 is a bound, not a chart); a simulation at rtol 1e-9
# is
# a time response to about its tolerance over a few periods (chaotic runs part later); a regime
# judged on a simulation is the classifier's verdict, 0 by definition.
FULL_MODEL_ERROR = {
    "frequency-response": 2e-8,
    "critical-forcing": 1e-6,
    "time-response": 1e-6,
    "regime": 0.0,
}
FULL_MODEL = {
    "frequency-response": "shooting on (9)",
    "critical-forcing": "shooting on (9): Abar_c over every family at sigma",
    "time-response": "smooth model (9) simulated",
    "regime": "smooth model (9) simulated and classified",
}


@dataclasses.dataclass(frozen=True)
class Answer:
    """What :func:`answer` did: the question, the model used and why, its error estimate, and the
    result (a FrequencyResponse / OrbitFamily, a CriticalPoint / FullCritical, a SlowTrajectory /
    Simulation, or a regime name with its evidence)."""

    question: str
    model: str
    reason: str
    error_estimate: float
    result: object
    seconds: float

    def summary(self) -> str:
        return f"{self.question}: {self.model} (error estimate {self.error_estimate:.2g}); {self.reason}"


def model_choice(question: str, params: Params, tol: float) -> tuple:
    """(model, reason, error estimate) that :func:`answer` would use, without running anything."""
    _check(question, params, tol)
    concerns = asymptotics_concerns(params)
    slow_error = SLOW_FLOW_ERROR[question]
    if concerns:
        why = "the slow flow is outside its checked range (" + "; ".join(concerns) + ")"
    elif slow_error <= tol:
        return SLOW_FLOW, f"its measured error {slow_error:g} is within the tolerance {tol:g}", slow_error
    else:
        why = f"the slow flow's measured error {slow_error:g} exceeds the tolerance {tol:g}"
    if question in CORRECTED_ERROR:
        corrected_concerns = asymptotics_concerns(params, "corrected")
        error = CORRECTED_ERROR[question]
        if not corrected_concerns and error <= tol:
            return CORRECTED, f"{why}; the corrected slow flow's measured error {error:g} is within it", error
        why += "; the corrected slow flow " + (
            f"is outside its range ({'; '.join(corrected_concerns)})"
            if corrected_concerns
            else f"measured {error:g}"
        )
    for model, errors, name, _ in _IMPACT_RUNGS:
        table = errors.get(question)
        if not table:
            continue
        measured = [n for n in table if n <= params.n]
        if not measured:
            why += f"; {name}'s error is not measured below n = {min(table)}"
        elif table[max(measured)] <= tol:
            error = table[max(measured)]
            return (
                model,
                f"{why}; {name}'s measured error at n >= {max(measured)}, {error:g}, is within it",
                error,
            )
        else:
            why += f"; {name} measured {table[max(measured)]:g} at n >= {max(measured)}"
    return FULL_MODEL[question], why, FULL_MODEL_ERROR[question]


def _check(question, params, tol):
    if question not in QUESTIONS:
        raise ValueError(f"question must be one of {', '.join(QUESTIONS)}; got {question!r}")
    if not isinstance(params, Params):
        raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol (the relative error allowed) must be a finite number > 0; got {tol!r}")


def answer(
    question: str,
    params: Params,
    *,
    tol: float = 0.05,
    state0=None,
    sigma_min=None,
    sigma_max=None,
    tmax: float = CLASSIFY_TMAX,
    progress=None,
) -> Answer:
    """Answer ``question`` for ``params`` with the lightest model whose measured error is within ``tol``.

    Parameters
    ----------
    question : str
        "frequency-response" (amplitude of X against sigma over [sigma_min, sigma_max]),
        "critical-forcing" (least Abar with a resonant response at params.sigma), "time-response"
        (X(tau) from ``state0`` to ``tmax``) or "regime" (response regime from ``state0``).
    state0 : array_like, optional
        Initial state [X, X', w, w'] (default: the Fig. 10 presets' kicked start).
    """
    model, reason, error = model_choice(question, params, tol)
    y0 = get_preset("fig10").state0 if state0 is None else np.asarray(state0, dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise ValueError(f"state0 must be 4 finite numbers [X, X', w, w']; got {state0!r}")
    if not (np.isfinite(tmax) and tmax > 8 * np.pi):
        raise ValueError(f"tmax must be finite and longer than 4 forcing periods (8 pi); got {tmax!r}")
    if question in ("time-response", "regime"):
        params.require_positive_stiffness()
    lo = params.sigma - 3.0 if sigma_min is None else float(sigma_min)
    hi = params.sigma + 3.0 if sigma_max is None else float(sigma_max)
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < params.sigma < hi):
        raise ValueError(f"need finite sigma_min < sigma = {params.sigma} < sigma_max; got {lo} and {hi}")
    say = progress or (lambda message: None)
    say(f"{question}: {model} ({reason})")
    start = time.perf_counter()
    result = None
    if model in (SLOW_FLOW, CORRECTED):
        with warnings.catch_warnings():
            warnings.simplefilter(
                "ignore", AsymptoticsWarning
            )  # the choice above already weighed the asymptotics
            result, escape, note = _slow(
                question, params, y0, lo, hi, tmax, "corrected" if model == CORRECTED else "slowflow"
            )
        if escape:  # the slow flow cannot answer after all: the full model must
            model, reason, error = FULL_MODEL[question], escape, FULL_MODEL_ERROR[question]
        reason += note
    variant = {m: v for m, _, _, v in _IMPACT_RUNGS}.get(model)
    if variant is not None:
        result = _impact(params, y0, lo, hi, variant)
    elif model not in (SLOW_FLOW, CORRECTED):  # shooting on (9), or (9) simulated
        result = _full(question, params, y0, lo, hi, tmax, say)
    return Answer(question, model, reason, float(error), result, time.perf_counter() - start)


def _slow(question, params, y0, lo, hi, tmax, model):
    """(result, reason to escalate or "", note for the reason) of the slow flow ``model``."""
    if question == "frequency-response":
        return frequency_response(params, sigma_min=lo, sigma_max=hi, model=model), "", ""
    if question == "critical-forcing":
        return critical_forcing(params, params.sigma, model=model), "", ""
    flow = SlowFlow(params)
    trajectory = flow.integrate(*flow.start_from_state(y0), (0.0, params.eps * tmax))
    if question == "time-response":
        # off S+ the slow flow says nothing more about X(tau)
        return trajectory, f"the slow flow leaves S+ ({trajectory.message})" if trajectory.escaped else "", ""
    regime = (
        "not resonant (non-resonant or strongly modulated)" if trajectory.escaped else "periodic-resonant"
    )
    return regime, "", f"; (45) from the initial state: {trajectory.message}"


def _impact(params, y0, lo, hi, variant):
    """The branch of orbits of the impact model ``variant`` through the one a simulation of it
    from y0 settles on (else from the slow flow's steady states over [lo, hi])."""
    start = impact_start(params, y0, periods=IMPACT_SETTLE, p_range=(lo, hi), variant=variant)
    return trace_impact_orbits(start.params, start.x, p_min=lo, p_max=hi, variant=variant)


IMPACT_SETTLE = 300  # forcing periods of (8) before Newton on its map


def _full(question, params, y0, lo, hi, tmax, say=None):
    if question in ("time-response", "regime"):
        sim = simulate(params, y0, tmax)
        return sim if question == "time-response" else classify(sim)
    if question == "critical-forcing":  # every family at sigma, not only the one y0 settles on
        return critical_forcing_full(params, y0, progress=say)
    orbit, _ = settle_and_shoot(params, y0)
    at, start = params, orbit.y0
    if not (orbit.converged and orbit.stable):  # as shoot starts: from the slow flow's steady states
        try:
            found = slow_flow_start(params, lo, hi)
        except (ConvergenceError, ValueError) as err:  # none of (9) from them, or no steady state
            raise RuntimeError(
                f"no stable periodic orbit of (9) is reached from state0 at sigma = {params.sigma}, "
                f"Abar = {params.Abar} within 1000 forcing periods (the response there is not periodic: "
                f"try the regime question), nor from the slow flow's steady states ({err})"
            ) from None
        at, start = found.params, found.y0
    return trace_orbits(at, start, branching=NO_SWITCHING, interval=ParameterRange(lo=lo, hi=hi))
