"""A ladder for frequency-response fits (``--model auto``): the models from the lightest up, the
slow flow (46), the corrected slow flow, the orbits of the vibro-impact model (8) and of the smooth
model (9), each fitted in turn; the first whose fit describes the data
(:mod:`.goodness`: p >= 0.001) and whose asymptotics hold at the estimate gives the answer. A slow
flow is not believed however well it fits where it can have absorbed its own error into the
parameters: outside the range where it was checked against (9) (eps <= 0.1, beta <= 0.5, a wall
losing at most half the energy per impact), or where the full model it expands (:data:`EXPANDS`:
(46) the vibro-impact model (8) with the restitution (21); the corrected slow flow, whose impacts
take the smooth wall's own kappa and clearance, (9)) does not describe the data at its estimate.
The rungs passed over are reported with why: their p-values, their concerns, or the error that
stopped them. (9), fitted as a check beside a lighter rung used, takes its place where its misfit
is lower by more than the likelihood ratio's 95 % threshold: a rung that describes the data at its
own p-value is not the answer where the data tell a better one from it."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from slosh_bif.identify.goodness import goodness
from slosh_bif.identify.response_fit import fit_response
from slosh_bif.identify.response_integers import INTEGERS
from slosh_bif.identify.response_objective import Objective
from slosh_bif.identify.response_result import MODEL_NAMES, SLOW_MODELS
from slosh_bif.identify.response_stats import CHI2_95
from slosh_bif.slowflow.flow import AsymptoticsWarning, asymptotics_concerns

__all__ = ["RUNGS", "EXPANDS", "fit_by_ladder", "unheld_by_expansion"]

RUNGS = ("slowflow", "corrected", "impact", "smooth")  # the lightest first
EXPANDS = {"slowflow": "impact", "corrected": "smooth"}  # the full model each slow flow expands


def _applies(model: str, free) -> str:
    """Why ``model`` cannot fit ``free`` ("" when it can)."""
    if model in SLOW_MODELS and "eps" in free:
        return "eps does not enter the slow flow"
    if model not in SLOW_MODELS and any(name in INTEGERS for name in free):
        return "n and pbar are profiled by the slow flows only"
    return ""


def fit_by_ladder(data, base, free, *, seed: int = 0, progress=None, pool=None):
    """The fit by the lightest model of :data:`RUNGS` that describes ``data``, its ``ladder``
    holding every rung tried with its verdict, and the heaviest rung fitted as a check where a
    lighter one is used (:func:`_against_heaviest`); where none is believed, the lightest whose fit
    describes the data with why it is doubted, else the last rung's fit, flagged;
    ``pool``: as for :func:`~.response_fit.fit_response`."""
    say = progress or (lambda message: None)
    fitting = {"seed": seed, "progress": progress, "pool": pool}
    rows, last, doubted = [], None, None
    for model in RUNGS:
        fit, why = _rung(data, base, free, model, say, fitting)
        if fit is None:
            rows.append({"model": model, "used": False, "why": why})
            continue
        last = fit
        p = fit.goodness.p_value
        if not why:
            rows.append({"model": model, "used": True, "why": f"describes the data (p = {p:.2g})"})
            return _against_heaviest(data, base, free, dataclasses.replace(fit, ladder=rows), say, fitting)
        rows.append({"model": model, "used": False, "why": why, "p_value": p, "values": fit.values})
        if doubted is None and fit.describes:
            doubted = (fit, why)
    if last is None:
        raise ValueError("no model of the ladder could fit these data: " + "; ".join(r["why"] for r in rows))
    if doubted is None:
        return dataclasses.replace(last, ladder=rows)
    # no rung believed, but a slow flow describes the data: its fit, with why it is doubted
    fit, why = doubted
    said = f"No model of the ladder is believed; {MODEL_NAMES[fit.model]} is reported: it {why}."
    return dataclasses.replace(
        fit, ladder=rows, not_identifiable=" ".join(filter(None, [said, fit.not_identifiable]))
    )


def _rung(data, base, free, model: str, say, fitting) -> tuple:
    """(the fit by ``model`` or None where it cannot fit, why it is not believed: "" where it is)."""
    why = _applies(model, free)
    if why:
        return None, why
    say(f"ladder: fitting by {MODEL_NAMES[model]}")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AsymptoticsWarning)
            fit = fit_response(data, base, free, model=model, **fitting)
    except ValueError as err:  # no response to compare a point with, an orbit lost, ...
        return None, str(err)
    p = fit.goodness.p_value
    concerns = asymptotics_concerns(fit.params(base), model) if model in SLOW_MODELS else []
    if not fit.describes:
        return fit, f"does not describe the data (p = {p:.2g})"
    if concerns:
        return fit, f"fits (p = {p:.2g}) but is outside its checked range: {'; '.join(concerns)}"
    unheld = unheld_by_expansion(data, fit.params(base), model, len(fit.free)) if model in SLOW_MODELS else ""
    if unheld:
        return fit, f"fits (p = {p:.2g}) but {unheld}"
    if not fit.converged:
        return fit, f"did not converge ({fit.message})"
    return fit, ""


def unheld_by_expansion(data, params, model: str, free: int) -> str:
    """Why the slow flow ``model``'s estimate ``params`` (``free`` parameters fitted) does not hold
    for the full model it expands, :data:`EXPANDS` ("" where it does): that model's responses at
    the estimate, not refitted, compared with the data (:mod:`.goodness`)."""
    full = EXPANDS[model]
    name = MODEL_NAMES[full]
    try:
        objective = Objective(data, params, (), full)
        r = objective(np.zeros(0))
    except ValueError as err:  # no response of the full model to follow at some point
        return f"at its estimate the model it expands ({name}) has no response to compare with: {err}"
    if objective.lost:
        return f"at its estimate the responses of the model it expands ({name}) are lost"
    verdict = goodness(data, r, free, name)
    if verdict.describes:
        return ""
    return (
        f"at its estimate the model it expands ({name}) does not describe the data "
        f"(p = {verdict.p_value:.2g}): the slow flow has absorbed its own error into the parameters"
    )


def _against_heaviest(data, base, free, fit, say, fitting):
    """``fit`` (a lighter rung's) with the heaviest rung fitted as a check, a row of the ladder
    (``checked``): where that rung's misfit is lower by more than the likelihood ratio's 95 %
    threshold, its fit instead (:func:`_preferred`); where it describes the data too but puts a
    free parameter's 95 % profile interval apart from ``fit``'s, the data do not tell the two
    models apart and the parameters depend on which one holds, which ``fit`` then says (the
    vibro-impact model (8) and (9) both describe the sweeps of ``examples/sweep_response.py``
    with gamma 0.54 and 0.28)."""
    heaviest = RUNGS[-1]
    if fit.model == heaviest or _applies(heaviest, free):
        return fit
    other, why = _rung(data, base, free, heaviest, say, fitting)
    row = {"model": heaviest, "used": False, "checked": True}
    if other is None or why:
        row["why"] = f"fitted as a check: {why}"
        return dataclasses.replace(fit, ladder=fit.ladder + [row])
    row |= {"p_value": other.goodness.p_value, "values": other.values}
    if fit.misfit - other.misfit > CHI2_95:
        return _preferred(fit, other)
    apart = [n for n in fit.free if _apart(fit.estimate[n]["profile_95"], other.estimate[n]["profile_95"])]
    if not apart:
        row["why"] = (
            f"fitted as a check: describes the data too (p = {other.goodness.p_value:.2g}), "
            "each interval meeting the used model's"
        )
        return dataclasses.replace(fit, ladder=fit.ladder + [row])
    values = ", ".join(
        f"{n} = {other.values[n]:.4g} (profile {_shown(other.estimate[n]['profile_95'])})" for n in apart
    )
    said = (
        f"Fitted by {MODEL_NAMES[heaviest]} as well, the data are described too (p = "
        f"{other.goodness.p_value:.2g}) with {values}, apart from the interval of {MODEL_NAMES[fit.model]}: "
        f"the data do not tell the two models apart, and {', '.join(apart)} "
        f"{'depends' if len(apart) == 1 else 'depend'} on which one the tank follows."
    )
    row["why"] = said
    return dataclasses.replace(
        fit, ladder=fit.ladder + [row], not_identifiable=" ".join(filter(None, [fit.not_identifiable, said]))
    )


def _preferred(fit, other):
    """``other`` (the heaviest rung's fit) in place of ``fit``, whose misfit it lowers by more than
    :data:`~.response_stats.CHI2_95` with as many parameters (the likelihood ratio's 95 % threshold,
    here the same difference of AIC): the data tell the two models apart, and ``fit`` describing
    them at its own p-value does not make it the answer."""
    lower = f"misfit {other.misfit:.4g} against {fit.misfit:.4g}, lower by more than {CHI2_95:.3g}"
    passed = {
        "model": fit.model,
        "used": False,
        "why": f"describes the data (p = {fit.goodness.p_value:.2g}), but {MODEL_NAMES[other.model]} "
        f"describes them better ({lower} with as many parameters)",
        "p_value": fit.goodness.p_value,
        "values": fit.values,
    }
    used = {
        "model": other.model,
        "used": True,
        "why": f"describes the data (p = {other.goodness.p_value:.2g}) better than {MODEL_NAMES[fit.model]}",
    }
    return dataclasses.replace(other, ladder=fit.ladder[:-1] + [passed, used])


def _apart(one, other) -> bool:
    """Whether two intervals [lo, hi] (None: unbounded) do not meet."""
    lo1, hi1 = (-np.inf if one[0] is None else one[0]), (np.inf if one[1] is None else one[1])
    lo2, hi2 = (-np.inf if other[0] is None else other[0]), (np.inf if other[1] is None else other[1])
    return hi1 < lo2 or hi2 < lo1


def _shown(interval) -> str:
    return "[" + ", ".join("..." if v is None else f"{v:.4g}" for v in interval) + "]"
