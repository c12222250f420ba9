"""The outputs of a frequency-response fit (:mod:`.response_fit`): ``fit.json`` (estimates, Wald
and profile intervals, correlations, what is not identifiable, the data file's SHA-256),
``fit.png`` (the measured points with the fitted response curve of (46), stable and unstable, and
the residuals), ``profiles.png`` (each free parameter's profile of the misfit) and
``params.toml``, the fitted set that every command takes with ``--params``."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from slosh_bif.atomic import write_text_atomically
from slosh_bif.identify.response_model import response_curve
from slosh_bif.identify.response_result import MODEL_NAMES, ORBIT_MODELS
from slosh_bif.identify.response_stats import CHI2_95
from slosh_bif.model.parameter_file import render_parameter_file
from slosh_bif.model.params import Params

__all__ = ["write_response_fit", "write_fit_outputs", "plot_profiles"]


def write_response_fit(fit, data, base: Params, folder) -> list:
    """Write fit.json, params.toml, fit.png and profiles.png into ``folder``; returns their paths."""
    fitted = fit.params(base)
    return write_fit_outputs(
        fit,
        data.source,
        fitted,
        folder,
        lambda path: _plot_fit(fit, data, fitted, path),
        MODEL_NAMES[fit.model],
    )


def write_fit_outputs(fit, source: str, fitted: Params, folder, plot, by: str) -> list:
    """fit.json (with the data file's SHA-256), params.toml (``fitted``, commented as fitted ``by``
    to ``source``), fit.png by ``plot(path)`` and profiles.png in ``folder``; their paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    record = fit.as_dict()
    if source and Path(source).is_file():
        record["data"] = {"file": source, "sha256": hashlib.sha256(Path(source).read_bytes()).hexdigest()}
    paths = [write_text_atomically(folder / "fit.json", json.dumps(record, indent=2) + "\n")]
    comment = f"fitted by `slosh-bif fit` ({by}) to {source or 'measurements'}"
    paths.append(
        write_text_atomically(folder / "params.toml", render_parameter_file(params=fitted, comment=comment))
    )
    paths.append(plot(folder / "fit.png"))
    paths.append(plot_profiles(fit, folder / "profiles.png"))
    return paths


def _branches(curve):
    """Polylines (sigma, A, stable) of the response curve: both roots of (46) on the amplitude
    grid, each cut into runs of one stability."""
    runs = []
    for sigma in (curve.sigma_low, curve.sigma_high):
        ok = np.isfinite(sigma)
        stable = np.array([curve.stable(a, s) if k else False for a, s, k in zip(curve.A, sigma, ok)])
        start = 0
        for i in range(1, len(sigma) + 1):
            if i == len(sigma) or ok[i] != ok[start] or stable[i] != stable[start]:
                if ok[start] and i - start > 1:
                    runs.append((sigma[start:i], curve.A[start:i], bool(stable[start])))
                start = i
    return runs


def _plot_fit(fit, data, fitted: Params, path) -> Path:
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(7.5, 6.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    scale = data.std if data.std is not None else 1.0
    x, unit, xlabel, units = data.axes()
    # the fitted model at the points: orbits, or steady states of each point's own set (data in Hz)
    if fit.model in ORBIT_MODELS or data.ratio is not None:
        order = np.argsort(x)
        model_A = (data.A - fit.residuals * scale)[order] * unit
        label = f"fitted: {MODEL_NAMES[fit.model]}"
        top.plot(x[order], model_A, "s", mfc="none", ms=7, color="tab:red", label=label)
    else:
        _plot_curve(top, response_curve(fitted, fit.model), data)
    for direction, marker in (("up", "^"), ("down", "v"), ("", "o")):
        pick = (
            np.array([s == direction for s in data.sweep])
            if data.sweep
            else np.full(len(data), direction == "")
        )
        if pick.any():
            yerr = data.std[pick] * unit if data.std is not None else None
            name = f"measured ({direction}-sweep)" if direction else "measured"
            top.errorbar(x[pick], data.A[pick] * unit, yerr=yerr, fmt=marker, ms=4, color="k", label=name)
    _plot_assignment(top, fit, x, unit)
    top.set_ylabel("amplitude A" + units)
    top.legend(fontsize=8)
    free = ", ".join(f"{k} = {v:.4g}" for k, v in fit.values.items())
    verdict = "" if fit.describes else "\nTHE FITTED MODEL DOES NOT DESCRIBE THESE DATA (p < 0.001)"
    top.set_title(f"frequency response fitted by {MODEL_NAMES[fit.model]}: {free}{verdict}", fontsize=9)
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.plot(x, fit.residuals, "o", ms=3, color="k")
    bottom.set_xlabel(xlabel)
    bottom.set_ylabel("residual / std" if data.std is not None else "residual")
    return save_figure(fig, path)


def _plot_assignment(ax, fit, x, unit):
    """Each point's stable candidates (grey ticks) and the one it is compared with (a thin line
    from the point to it); the points no stable response explains circled."""
    if not fit.assignment:
        return
    ticks = [(x[i], a * unit) for i, row in enumerate(fit.assignment) for a in row["stable_candidates"]]
    if ticks:
        tx, ty = zip(*ticks)
        ax.plot(tx, ty, "_", ms=10, mew=1.2, color="0.55", label="stable responses at each point")
    for i, row in enumerate(fit.assignment):
        ax.plot([x[i], x[i]], [row["A"] * unit, row["model_A"] * unit], "-", color="tab:red", lw=0.6)
    bad = [i for i, row in enumerate(fit.assignment) if not row["explained"]]
    if bad:
        ax.plot(
            [x[i] for i in bad],
            [fit.assignment[i]["A"] * unit for i in bad],
            "o",
            ms=11,
            mfc="none",
            color="tab:red",
            label="explained by no stable response",
        )


def _plot_curve(ax, curve, data):
    """The response curve of (46) over the data's sigma range, stable solid and unstable dashed."""
    lo, hi = float(data.sigma.min()), float(data.sigma.max())
    pad = 0.1 * (hi - lo or 1.0)
    labelled = set()
    for sigma, A, stable in _branches(curve):
        keep = (sigma >= lo - pad) & (sigma <= hi + pad)
        if not keep.any():
            continue
        label = ("fitted (46): stable" if stable else "unstable") if stable not in labelled else None
        labelled.add(stable)
        ax.plot(sigma[keep], A[keep], "-" if stable else "--", color="tab:red", lw=1.2, label=label)


def plot_profiles(fit, path) -> Path:
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    names = list(fit.profiles) or ["(none)"]
    fig, axes = plt.subplots(1, len(names), figsize=(3.6 * len(names), 3.2), squeeze=False)
    for ax, name in zip(axes[0], names):
        if name in fit.profiles:
            rows = np.array(fit.profiles[name])
            ax.plot(rows[:, 0], rows[:, 1], "o-", ms=3, color="k")
            ax.axhline(CHI2_95, color="tab:red", lw=0.8, ls="--", label="95 % (3.84)")
            ax.set_ylim(-0.3, min(float(rows[:, 1].max()), 4 * CHI2_95) * 1.05 + 0.3)  # the crossing in view
            for bound in fit.estimate[name]["profile_95"]:
                if bound is not None:
                    ax.axvline(bound, color="tab:red", lw=0.8)
            ax.set_xlabel(name)
            ax.legend(fontsize=7)
        else:
            ax.text(0.5, 0.5, "no continuous parameter", ha="center", va="center", transform=ax.transAxes)
    axes[0][0].set_ylabel("misfit rise, the others refitted")
    fig.suptitle("profile likelihood of each free parameter", fontsize=9)
    return save_figure(fig, path)
