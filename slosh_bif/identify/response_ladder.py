"""A ladder for frequency-response fits (``--model auto``): the models from the lightest up, the
slow flow (46), the corrected slow flow, the orbits of the vibro-impact model (8) and of the smooth
model (9), each fitted in turn; the first whose fit describes the data
(:mod:`.goodness`: p >= 0.001) and whose asymptotics hold at the estimate (a slow flow outside the
range where it was checked against (9), eps <= 0.1, beta <= 0.5, a wall losing at most half the
energy per impact, is not believed however well it fits: it can absorb its own error into the
damping) gives the answer. The rungs passed over are reported with why: their p-values, their
concerns, or the error that stopped them."""

from __future__ import annotations

import dataclasses
import warnings

from slosh_bif.identify.response_fit import fit_response
from slosh_bif.identify.response_integers import INTEGERS
from slosh_bif.identify.response_result import MODEL_NAMES, SLOW_MODELS
from slosh_bif.slowflow.flow import AsymptoticsWarning, asymptotics_concerns

__all__ = ["RUNGS", "fit_by_ladder"]

RUNGS = ("slowflow", "corrected", "impact", "smooth")  # the lightest first


def _applies(model: str, free) -> str:
    """Why ``model`` cannot fit ``free`` ("" when it can)."""
    if model in SLOW_MODELS and "eps" in free:
        return "eps does not enter the slow flow"
    if model not in SLOW_MODELS and any(name in INTEGERS for name in free):
        return "n and pbar are profiled by the slow flows only"
    return ""


def fit_by_ladder(data, base, free, *, seed: int = 0, progress=None, pool=None):
    """The fit by the lightest model of :data:`RUNGS` that describes ``data``, its ``ladder``
    holding every rung tried with its verdict (the last rung's fit, flagged, where none does);
    ``pool``: as for :func:`~.response_fit.fit_response`."""
    say = progress or (lambda message: None)
    rows, last = [], None
    for model in RUNGS:
        why = _applies(model, free)
        if why:
            rows.append({"model": model, "used": False, "why": why})
            continue
        say(f"ladder: fitting by {MODEL_NAMES[model]}")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", AsymptoticsWarning)
                fit = fit_response(data, base, free, model=model, seed=seed, progress=progress, pool=pool)
        except ValueError as err:  # no response to compare a point with, an orbit lost, ...
            rows.append({"model": model, "used": False, "why": str(err)})
            continue
        last = fit
        p = fit.goodness.p_value
        concerns = asymptotics_concerns(fit.params(base), model) if model in SLOW_MODELS else []
        if not fit.describes:
            why = f"does not describe the data (p = {p:.2g})"
        elif concerns:
            why = f"fits (p = {p:.2g}) but is outside its checked range: {'; '.join(concerns)}"
        elif not fit.converged:
            why = f"did not converge ({fit.message})"
        else:
            rows.append({"model": model, "used": True, "why": f"describes the data (p = {p:.2g})"})
            return dataclasses.replace(fit, ladder=rows)
        rows.append({"model": model, "used": False, "why": why, "p_value": p, "values": fit.values})
    if last is None:
        raise ValueError("no model of the ladder could fit these data: " + "; ".join(r["why"] for r in rows))
    return dataclasses.replace(last, ladder=rows)
