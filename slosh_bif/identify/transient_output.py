"""The outputs of a fit to a record from a known start by the trajectory of (9) or (8)
(:mod:`.transient_fit`): fit.json, params.toml and profiles.png as for a frequency response, and
fit.png: the record with the fitted trajectory, the horizon marked (beyond it the trajectory is a
prediction, not fitted), and the residuals up to the horizon."""

from __future__ import annotations

import numpy as np

from slosh_bif.identify.response_output import write_fit_outputs
from slosh_bif.identify.transient_fit import TransientFit
from slosh_bif.identify.transient_record import TRAJECTORY_NAMES, TransientRecord
from slosh_bif.model.params import Params

__all__ = ["write_transient_fit"]


def write_transient_fit(fit: TransientFit, record: TransientRecord, base: Params, folder) -> list:
    """Write fit.json, params.toml, fit.png and profiles.png into ``folder``; returns their paths."""
    by = f"{'a forced transient' if fit.forced else 'a free decay'} by {TRAJECTORY_NAMES[fit.model]}"
    return write_fit_outputs(
        fit, record.source, fit.params(base), folder, lambda p: _plot(fit, record, p), by
    )


def _plot(fit: TransientFit, record: TransientRecord, path):
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(8, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    top.plot(record.tau, record.X, ".", ms=2, color="k", label="record")
    X = np.array([np.nan if x is None else x for x in fit.trajectory["X"]], dtype=float)
    head = record.tau <= fit.horizon
    top.plot(record.tau[head], X[head], color="tab:red", lw=1, label=f"fitted: {TRAJECTORY_NAMES[fit.model]}")
    top.plot(
        record.tau[~head], X[~head], color="tab:orange", lw=0.8, label="its prediction beyond the horizon"
    )
    for ax in (top, bottom):
        ax.axvline(fit.horizon, color="0.5", ls="--", lw=0.8)
    top.set_ylabel("vessel X")
    top.legend(fontsize=8, loc="upper right")
    values = ", ".join(f"{k} = {v:.4g}" for k, v in fit.values.items())
    verdict = "" if fit.describes else "\nTHE FITTED MODEL DOES NOT DESCRIBE THESE DATA (p < 0.001)"
    top.set_title(
        f"{'forced transient' if fit.forced else 'free decay'} fitted to tau = "
        f"{fit.horizon:.4g} (dashed): {values}{verdict}",
        fontsize=9,
    )
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.plot(record.tau[: len(fit.residuals)], fit.residuals, ".", ms=2, color="k")
    ahead = (record.X - X)[~head] / (record.std[~head] if record.std is not None else 1.0)
    bottom.plot(record.tau[~head], ahead, ".", ms=1, color="tab:orange")
    bottom.set_xlabel("tau")
    bottom.set_ylabel("residual / std" if record.std is not None else "residual")
    return save_figure(fig, path)
