"""The outputs of a fit to a settled forced record (:mod:`.steady_fit`): fit.json, params.toml and
profiles.png as for a frequency response, and fit.png: the record folded onto one forcing period
over the fitted orbit of (9) or (8) (each frequency's record over its own orbit), and the residuals
along time."""

from __future__ import annotations

import numpy as np

from slosh_bif.identify.response_output import write_fit_outputs
from slosh_bif.identify.response_result import MODEL_NAMES
from slosh_bif.identify.steady_fit import SteadyFit
from slosh_bif.identify.steady_record import SteadyRecord
from slosh_bif.model.params import Params

__all__ = ["write_steady_fit"]


def write_steady_fit(fit: SteadyFit, record: SteadyRecord, base: Params, folder) -> list:
    """Write fit.json, params.toml, fit.png and profiles.png into ``folder``; returns their paths."""
    by = f"a settled forced record by {MODEL_NAMES[fit.model]}"
    return write_fit_outputs(
        fit, record.source, fit.params(base), folder, lambda path: _plot(fit, record, path), by
    )


def _plot(fit: SteadyFit, record: SteadyRecord, path):
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6.5), gridspec_kw={"height_ratios": [3, 1]})
    several = len(fit.orbits) > 1
    for k, (curve, (sigma, rows)) in enumerate(zip(fit.orbits, record.parts(fit.orbits[0]["sigma"]))):
        color = f"C{k}" if several else "k"
        yerr = record.std[rows] if record.std is not None else None
        what = f"record at sigma = {sigma:g}" if several else "record"
        top.errorbar(
            np.mod(record.tau[rows], 2 * np.pi),
            record.X[rows],
            yerr=yerr,
            fmt="o",
            ms=3,
            color=color,
            label=f"{what}, folded on the forcing period",
        )
        style = "-" if curve["stable"] else "--"
        label = ("its orbit, fitted" if several else f"fitted: {MODEL_NAMES[fit.model]}") + (
            "" if curve["stable"] else " (unstable)"
        )
        top.plot(curve["phase"], curve["X"], style, color="tab:red" if not several else color, label=label)
        bottom.plot(record.tau[rows], fit.residuals[rows], "o", ms=3, color=color)
    top.set_xlabel("tau mod 2pi (the forcing's phase)")
    top.set_ylabel("vessel X")
    top.legend(fontsize=8)
    values = ", ".join(f"{k} = {v:.4g}" for k, v in fit.values.items())
    verdict = "" if fit.describes else "\nTHE FITTED MODEL DOES NOT DESCRIBE THESE DATA (p < 0.001)"
    by = f" by {MODEL_NAMES[fit.model]}" if several else ""
    top.set_title(f"settled record{'s' if several else ''} fitted{by}: {values}{verdict}", fontsize=9)
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.set_xlabel("tau")
    bottom.set_ylabel("residual / std" if record.std is not None else "residual")
    return save_figure(fig, path)
