"""Files of ``slosh-bif simulate`` (trajectory.npz, summary.json, simulate.png as in Figs. 9-13)
and of ``slosh-bif regimes`` (regimes.csv, regimes.png).

The figure shows the time histories of X and w, the per-period envelope of X with A_min, and the
trajectory's projection on the slow invariant manifold (36): one (A, alpha) point per forcing
period over both branches of the manifold.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from slosh_bif.model.manifold import project_on_manifold
from slosh_bif.model.restitution.on_manifold import ManifoldLaw
from slosh_bif.report.files import CellStore, replaced_atomically, write_text_atomically
from slosh_bif.report.plotting import (
    cell_edges,
    plot_projection,
    plot_slow_manifold,
    plot_time_history,
    pyplot,
    save_figure,
)
from slosh_bif.report.tables import write_rows
from slosh_bif.simulation.regimes import RegimeSummary

__all__ = [
    "write_trajectory",
    "write_summary",
    "plot_simulation",
    "plot_motion_on_manifold",
    "summary_record",
    "write_regime_csv",
    "plot_regime_map",
    "draw_regimes",
    "regime_settings",
    "regime_store",
]


def write_trajectory(sim, path) -> Path:
    """tau, X, X', w, w' and the impacts (times, wall side, w' before and after) as one npz."""
    with replaced_atomically(path) as tmp:
        np.savez_compressed(
            tmp,
            tau=sim.t,
            X=sim.y[0],
            Xd=sim.y[1],
            w=sim.y[2],
            wd=sim.y[3],
            impact_t=sim.impact_t,
            impact_side=sim.impact_side,
            impact_v_minus=sim.impact_v_minus,
            impact_v_plus=sim.impact_v_plus,
            model=np.array(sim.model),
            status=np.array(sim.status),
        )
    return Path(path)


def summary_record(sim, summary) -> dict:
    """The regime summary with the run's model, parameters, status, noise and cost."""
    record = summary.as_dict()
    record.update(
        model=sim.model,
        params=sim.params.as_dict(),
        status=sim.status,
        message=sim.message,
        tau_start=float(sim.t[0]),
        tau_end=float(sim.t[-1]),
        impacts_total=int(sim.impact_t.size),
        seconds=round(sim.seconds, 3),
        noise=None
        if sim.noise is None
        else {
            "std": sim.noise.std,
            "cutoff": sim.noise.cutoff,
            "seed": sim.noise.seed,
            "modes": sim.noise.modes,
        },
    )
    return record


def write_summary(sim, summary, path) -> Path:
    return write_text_atomically(path, json.dumps(summary_record(sim, summary), indent=2) + "\n")


def plot_simulation(sim, summary, path, *, title: str = "") -> Path:
    """Time histories, envelope and the projection on the manifold, as one PNG."""
    plt = pyplot()
    fig = plt.figure(figsize=(11, 7.5))
    grid = fig.add_gridspec(2, 2, width_ratios=[1.7, 1])
    ax_t = fig.add_subplot(grid[0, 0])
    ax_e = fig.add_subplot(grid[1, 0], sharex=ax_t)
    ax_m = fig.add_subplot(grid[:, 1])

    plot_time_history(ax_t, sim.t, sim.y)
    ax_t.axvline(summary.transient, color="0.5", lw=0.8, ls=":")
    ax_t.legend(loc="upper right", fontsize=8)
    ax_t.set_ylabel("X, w")
    ax_t.set_title(title or f"{sim.model} model: {summary.regime}")

    proj = project_on_manifold(sim.t, sim.y)
    ax_e.plot(proj.t, proj.A, ".-", color="tab:blue", ms=2, lw=0.6, label="A: peak |X| per period")
    A_min = _a_min(sim, summary)
    ax_e.axhline(A_min, color="k", ls="--", lw=0.8, label=f"A_min = {A_min:.3g}")
    if sim.impact_t.size:
        ax_i = ax_e.twinx()
        edges = np.arange(sim.t[0], sim.t[-1] + 2 * np.pi, 2 * np.pi)
        counts, _ = np.histogram(sim.impact_t, edges)
        window = min(10, counts.size)  # a 10-period running mean: single periods give 0-4 and hide the trend
        mean = np.convolve(counts, np.ones(window) / window, mode="valid")
        centres = np.convolve(0.5 * (edges[1:] + edges[:-1]), np.ones(window) / window, mode="valid")
        ax_i.plot(centres, mean, color="tab:red", lw=0.8, alpha=0.7)
        ax_i.set_ylabel("impacts per period (10-period mean)", color="tab:red")
    ax_e.axvline(summary.transient, color="0.5", lw=0.8, ls=":")
    ax_e.set_xlabel(r"$\tau$")
    ax_e.set_ylabel("envelope of X")
    ax_e.legend(loc="upper left", fontsize=8)

    plot_motion_on_manifold(ax_m, sim, summary, proj)
    return save_figure(fig, path)


def _a_min(sim, summary) -> float:
    """The manifold's A_min (36): the summary's, or the parameter set's where the run was not judged."""
    return summary.A_min if np.isfinite(summary.A_min) else ManifoldLaw(sim.params).A_min


def plot_motion_on_manifold(ax, sim, summary, proj):
    """The manifold's branches, the trajectory's (A, alpha) per period, and the impact counts (a
    run stopped before a period's peak, or one not judged, still gets the manifold drawn)."""
    law, A_min = ManifoldLaw(sim.params), _a_min(sim, summary)
    peaks = proj.A[np.isfinite(proj.A)]
    A_top = max(3 * A_min, 1.15 * float(np.max(peaks)) if peaks.size else 1.0)
    plot_slow_manifold(ax, law, A_top)
    plot_projection(ax, proj, label="trajectory, one point per period")
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(
        f"{summary.impacts_per_period:.2f} impacts, {summary.crossings_per_period:.2f} crossings per period"
        if np.isfinite(summary.impacts_per_period)
        else "impacts and crossings per period not counted: the run was not judged",
        fontsize=9,
    )
    return ax


# --- regime maps (slosh-bif regimes) ----------------------------------------------------------

REGIME_COLORS = {
    "periodic-resonant": "tab:green",
    "non-resonant": "tab:blue",
    "strongly-modulated": "tab:red",
    "free-decay": "tab:olive",
    "other": "tab:gray",
    "diverged": "tab:brown",
    "failed": "black",
    "not computed": "white",
}
REGIME_COLUMNS = (
    "sigma",
    "Abar",
    "regime",
    "impacts_per_period",
    "crossings_per_period",
    "envelope_min",
    "envelope_max",
    "modulation",
    "collapses",
    "reason",
)


def write_regime_csv(rmap, path) -> Path:
    """One row per grid point: sigma, Abar, the regime and the measurements behind it."""
    rows = (
        {**dataclasses.asdict(rmap.summaries[i][j]), "sigma": float(s), "Abar": float(a)}
        for i, a in enumerate(rmap.Abar)
        for j, s in enumerate(rmap.sigma)
    )
    return write_rows(rows, REGIME_COLUMNS, path, digits=8)


def regime_settings(params, state0, sigmas, abars, *, tmax, model) -> dict:
    """What decides every cell of a regime map: a resumed run reuses stored cells only when these
    are equal (exactly: the grids as written by ``repr`` of their floats)."""
    return {
        "params": params.as_dict(),
        "state0": [float(v) for v in state0],
        "sigma": [float(v) for v in sigmas],
        "Abar": [float(v) for v in abars],
        "tmax": float(tmax),
        "model": model,
    }


def regime_store(path, settings: dict, *, resume: bool) -> CellStore:
    """``regimes.json``: the settings and every classified cell at full precision (what
    ``regimes --resume`` reads; regimes.csv rounds), stored as cells finish (see
    :class:`~slosh_bif.report.files.CellStore`)."""
    return CellStore(
        path,
        settings,
        resume=resume,
        encode=lambda summary: summary.as_dict(),
        decode=RegimeSummary.from_dict,
    )


def draw_regimes(ax, rmap, *, alpha=0.75):
    """The regimes of a :class:`RegimeMap` as coloured cells on ``ax``, with a legend entry per
    regime; returns the cell edges in sigma and Abar."""
    codes = {name: k for k, name in enumerate(REGIME_COLORS)}
    grid = np.vectorize(lambda r: codes.get(r, codes["other"]))(rmap.regime).astype(float)
    from matplotlib.colors import ListedColormap

    sigma_edges, abar_edges = cell_edges(rmap.sigma), cell_edges(rmap.Abar)
    ax.pcolormesh(
        sigma_edges,
        abar_edges,
        grid,
        cmap=ListedColormap(list(REGIME_COLORS.values())),
        vmin=-0.5,
        vmax=len(codes) - 0.5,
        alpha=alpha,
    )
    present = set(rmap.regime.ravel())
    for name, color in REGIME_COLORS.items():
        if name in present:  # the legend lists what the map shows
            ax.plot([], [], "s", color=color, ms=9, label=f"regime: {name}")
    return sigma_edges, abar_edges


def plot_regime_map(rmap, path, *, critical=None) -> Path:
    """The regimes as coloured cells over (sigma, Abar), with the slow flow's Abar_b(sigma) on top.

    ``critical`` is a :class:`~slosh_bif.slowflow.critical.CriticalCurve` (or None): above it the slow
    flow (45) has a steady state on the stable manifold branch S+.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    sigma_edges, abar_edges = draw_regimes(ax, rmap, alpha=0.75)
    if critical is not None:
        ax.plot(
            critical.sigma,
            critical.Abar_b,
            "k-",
            lw=2,
            label=r"slow flow: $\bar A_b(\sigma)$ (steady state on $S^+$ above)",
        )
    ax.set_xlim(sigma_edges[[0, -1]])
    ax.set_ylim(abar_edges[[0, -1]])
    ax.set_xlabel(r"detuning $\sigma$")
    ax.set_ylabel(r"forcing amplitude $\bar A$")
    ax.set_title(
        f"response regimes, {rmap.model} model, tau in [0, {rmap.tmax:g}] (classified on the second half)",
        fontsize=9,
    )
    ax.legend(loc="upper left", fontsize=8, framealpha=0.9)
    return save_figure(fig, path)
