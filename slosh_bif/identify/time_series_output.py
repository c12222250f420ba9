"""The outputs of a fit to a record in time (:mod:`.time_series`): fit.json, params.toml and
profiles.png as for a frequency response, and fit.png: the measured envelope with the fitted
amplitude (the slow flow on S+ to A_min, the linear flight's relaxation below it) and the
residuals."""

from __future__ import annotations

import numpy as np

from slosh_bif.identify.response_output import write_fit_outputs
from slosh_bif.identify.time_series import TimeRecord, TimeSeriesFit, record_amplitudes
from slosh_bif.model.params import Params
from slosh_bif.slowflow.flow import SlowFlow

__all__ = ["write_time_series_fit"]


def write_time_series_fit(fit: TimeSeriesFit, data: TimeRecord, base: Params, folder) -> list:
    """Write fit.json, params.toml, fit.png and profiles.png into ``folder``; returns their paths."""
    fitted = fit.params(base)
    by = f"{'a forced record' if fit.forced else 'a free decay'} by the slow flow ({fit.model})"
    return write_fit_outputs(
        fit, data.source, fitted, folder, lambda path: _plot(fit, data, fitted, path), by
    )


def _plot(fit: TimeSeriesFit, data: TimeRecord, fitted: Params, path):
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(7.5, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    tau = np.linspace(data.tau[0], data.tau[-1], 400)
    top.plot(data.tau, data.A, "o", ms=3, color="k", label="measured envelope")
    model = record_amplitudes(
        fitted, fit.values["A0"], tau, fit.model, forced=fit.forced, psi0=fit.values.get("psi0", 0.0)
    )
    top.plot(tau, model, color="tab:red", label="fitted")
    top.axhline(SlowFlow(fitted, fit.model).A_min, color="0.6", lw=0.8, ls="--", label="A_min")
    top.set_ylabel("amplitude A")
    top.legend(fontsize=8)
    top.set_title(
        ("forced record" if fit.forced else "free decay")
        + " fitted: "
        + ", ".join(f"{k} = {v:.4g}" for k, v in fit.values.items()),
        fontsize=9,
    )
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.plot(data.tau, fit.residuals, "o", ms=3, color="k")
    bottom.set_xlabel("tau")
    bottom.set_ylabel("residual / std" if data.std is not None else "residual")
    return save_figure(fig, path)
