"""The chart as files: ``curves.csv`` (one row per curve point, in curve order), ``critical.csv``
(Abar_b of (46) against Abar_c of (9) on a sigma grid), ``chart.png``, and the curve store
``curves/`` (each curve's ``.npz`` as it finishes: what ``chart --resume`` reuses).

``curves.csv`` columns: ``curve`` (number), ``kind`` (LP, PD, NS or BP), ``sigma``, ``Abar`` (or the
chart's second parameter), ``A1`` and
``max_abs_w`` (the orbit there), ``codim2`` (empty or CP, LPPD, LPNS, PDNS, R1-R4), ``bounds_stable``
(1 when every multiplier but the critical one(s) is inside the unit circle), ``status`` (the curve's:
``ok`` when it left the box or closed, else why it stopped) and ``origin``. A start from which no
curve could be started has one row at the start point, its status ``failed to start: <reason>``.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np

from slosh_bif.orbits.codim2 import CODIM2_KINDS, BifurcationCurve
from slosh_bif.report.files import DAMAGE, damaged, read_store, write_text_atomically
from slosh_bif.report.tables import write_rows
from slosh_bif.studies.chart import CRITICAL_COLUMNS, critical_rows, lowest_stable_boundary

__all__ = ["CURVE_COLUMNS", "curve_rows", "write_curves_csv", "write_critical_csv", "plot_chart", "chart_settings", "curve_store", "curve_columns"]

CURVE_COLUMNS = ("curve", "kind", "sigma", "Abar", "A1", "max_abs_w", "codim2", "bounds_stable", "status", "origin")


def curve_columns(second: str = "Abar") -> tuple:
    """The columns of ``curves.csv`` for a chart in (sigma, ``second``)."""
    return tuple(second if name == "Abar" else name for name in CURVE_COLUMNS)


def curve_rows(chart):
    for k, c in enumerate(chart.curves):
        labels = c.branch.special_labels()
        for i in range(len(c)):
            yield {
                "curve": k, "kind": c.kind, "sigma": float(c["sigma"][i]), chart.second: float(c[chart.second][i]), "A1": float(c["A1"][i]),
                "max_abs_w": float(c["max_abs_w"][i]), "codim2": labels[i] if labels[i] in CODIM2_KINDS else "",
                "bounds_stable": int(c.branch.stable[i]), "status": c.status, "origin": c.origin,
            }
    for k, f in enumerate(chart.failures, start=len(chart.curves)):  # a start that gave no curve: one row at the start point
        yield {
            "curve": k, "kind": f.kind, "sigma": f.sigma, chart.second: f.value, "A1": np.nan, "max_abs_w": np.nan, "codim2": "", "bounds_stable": "",
            "status": f"failed to start: {f.reason}", "origin": f.origin,
        }


def write_curves_csv(chart, path) -> Path:
    return write_rows(curve_rows(chart), curve_columns(chart.second), path)


def write_critical_csv(chart, path) -> Path:
    return write_rows(critical_rows(chart), CRITICAL_COLUMNS, path)


_LABELLED = 30  # codimension-2 points labelled on the chart at most


def plot_chart(chart, path, *, regimes=None) -> Path:
    """The curves (solid where they bound stable orbits), codimension-2 points, Abar_b of (46),
    Abar_c of (9), and the regime map behind them when given."""
    from slosh_bif.report.plotting import pyplot, save_figure

    fig, ax = pyplot().subplots(figsize=(11.5, 6.5))
    if regimes is not None:
        from slosh_bif.simulation.output import draw_regimes

        draw_regimes(ax, regimes, alpha=0.35)
    colors = {"LP": "tab:red", "PD": "tab:blue", "NS": "tab:purple", "BP": "tab:orange"}
    labelled = sum(len(c.codim2_points()) for c in chart.curves) <= _LABELLED  # beyond that the labels hide the curves
    for k, c in enumerate(chart.curves):
        s, a, st = c["sigma"], c[chart.second], c.branch.stable
        ax.plot(s, np.where(st, a, np.nan), "-", color=colors[c.kind], lw=1.6, label=f"{c.kind} curve" if k == [d.kind for d in chart.curves].index(c.kind) else None)
        ax.plot(s, np.where(st, np.nan, a), ":", color=colors[c.kind], lw=1.0)
        for label, sigma, abar in c.codim2_points():
            ax.plot(sigma, abar, "k*", ms=9 if labelled else 6)
            if labelled:
                ax.annotate(label, (sigma, abar), textcoords="offset points", xytext=(4, 4), fontsize=8)
    slow = chart.slow_flow_critical
    if slow is not None and len(slow.sigma):
        ax.plot(slow.sigma, slow.Abar_b, "k--", lw=1.4, label=r"slow flow $\bar A_b$ " + ("(46)" if slow.model == "slowflow" else "(corrected)"))
    if chart.second == "Abar":
        grid = np.linspace(*chart.sigma_range, 201)
        full = [lowest_stable_boundary(chart.curves, sigma)[0] for sigma in grid]
        ax.plot(grid, full, "-", color="tab:green", lw=3, alpha=0.6, label=r"full model $\bar A_c$ (9)")
    ax.plot([], [], "k*", label="codimension-2 point" + ("" if labelled else " (labels in curves.csv)"))
    ax.plot([], [], "k:", label="curve not bounding stable orbits")
    ax.set_xlim(*chart.sigma_range)
    ax.set_ylim(*chart.abar_range)
    ax.set_xlabel(r"detuning $\sigma$")
    ax.set_ylabel(r"forcing $\bar A$" if chart.second == "Abar" else chart.second)
    P = chart.params
    partial = "" if chart.status == "complete" else f"\nPARTIAL: {chart.status}"
    held = ", ".join(f"{name} = {getattr(P, name):g}" for name in ("eps", "beta", "gamma", "Abar", "n") if name != chart.second)
    ax.set_title(f"Orbit bifurcations of (9) in (sigma, {chart.second}): {held}{partial}")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.grid(alpha=0.3)
    return save_figure(fig, path)


def chart_settings(params, state0, sigma_range, abar_range, **options) -> dict:
    """What decides the chart's starts and curves: a resumed run reuses stored curves only when
    these are equal."""
    return {
        "params": params.as_dict(), "state0": [float(v) for v in state0], "sigma_range": [float(v) for v in sigma_range],
        "abar_range": [float(v) for v in abar_range], **options,
    }


def curve_store(folder, settings: dict, *, resume: bool):
    """(done, keep) for :func:`~slosh_bif.studies.chart.bifurcation_chart`: the curves stored in
    ``folder`` by an earlier run with the same ``settings`` (resume; else none, and the folder's
    old curves are removed), and a callback that stores each new curve there as it finishes
    (``curve-<start>.npz``, written atomically). A one-line ValueError when resuming from a
    missing or different store."""
    folder = Path(folder)
    marker = folder / "settings.json"
    if resume:
        read_store(marker, settings, key=None)
        done = {}
        for path in sorted(folder.glob("curve-*.npz")):
            try:
                done[int(path.stem.split("-")[1])] = BifurcationCurve.load(path)
            except (zipfile.BadZipFile, *DAMAGE) as err:
                raise damaged(path, err) from None
    else:
        folder.mkdir(parents=True, exist_ok=True)
        for path in folder.glob("curve-*.npz"):
            path.unlink()
        write_text_atomically(marker, json.dumps(settings) + "\n")
        done = {}

    def keep(i, curve):
        curve.save(folder / f"curve-{i:04d}.npz")

    return done, keep
