"""The chart as files: ``curves.csv`` (one row per curve point, in curve order), ``critical.csv``
(Abar_b of (46) against Abar_c of (9) on a sigma grid) and ``chart.png``.

``curves.csv`` columns: ``curve`` (number), ``kind`` (LP, PD or NS), ``sigma``, ``Abar``, ``A1`` and
``max_abs_w`` (the orbit there), ``codim2`` (empty or CP, LPPD, LPNS, PDNS, R1-R4), ``bounds_stable``
(1 when every multiplier but the critical one(s) is inside the unit circle), ``status`` (the curve's:
``ok`` when it left the box or closed, else why it stopped) and ``origin``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.orbits.codim2 import CODIM2_KINDS
from slosh_bif.report.tables import write_rows
from slosh_bif.studies.chart import CRITICAL_COLUMNS, critical_rows

__all__ = ["CURVE_COLUMNS", "curve_rows", "write_curves_csv", "write_critical_csv", "plot_chart"]

CURVE_COLUMNS = ("curve", "kind", "sigma", "Abar", "A1", "max_abs_w", "codim2", "bounds_stable", "status", "origin")


def curve_rows(chart):
    for k, c in enumerate(chart.curves):
        labels = c.branch.special_labels()
        for i in range(len(c)):
            yield dict(
                curve=k, kind=c.kind, sigma=float(c["sigma"][i]), Abar=float(c["Abar"][i]), A1=float(c["A1"][i]),
                max_abs_w=float(c["max_abs_w"][i]), codim2=labels[i] if labels[i] in CODIM2_KINDS else "",
                bounds_stable=int(c.branch.stable[i]), status=c.status, origin=c.origin,
            )


def write_curves_csv(chart, path) -> Path:
    return write_rows(curve_rows(chart), CURVE_COLUMNS, path)


def write_critical_csv(chart, path) -> Path:
    return write_rows(critical_rows(chart), CRITICAL_COLUMNS, path)


def plot_chart(chart, path, *, regimes=None) -> Path:
    """The curves (solid where they bound stable orbits), codimension-2 points, Abar_b of (46),
    Abar_c of (9), and the regime map behind them when given."""
    from slosh_bif.report.plotting import pyplot, save_figure

    fig, ax = pyplot().subplots(figsize=(9, 6.5))
    if regimes is not None:
        from slosh_bif.simulation.output import draw_regimes

        draw_regimes(ax, regimes, alpha=0.35)
    colors = {"LP": "tab:red", "PD": "tab:blue", "NS": "tab:purple", "BP": "tab:orange"}
    for k, c in enumerate(chart.curves):
        s, a, st = c["sigma"], c["Abar"], c.branch.stable
        ax.plot(s, np.where(st, a, np.nan), "-", color=colors[c.kind], lw=1.6, label=f"{c.kind} curve" if k == [d.kind for d in chart.curves].index(c.kind) else None)
        ax.plot(s, np.where(st, np.nan, a), ":", color=colors[c.kind], lw=1.0)
        for label, sigma, abar in c.codim2_points():
            ax.plot(sigma, abar, "k*", ms=9)
            ax.annotate(label, (sigma, abar), textcoords="offset points", xytext=(4, 4), fontsize=8)
    slow = chart.slow_flow_critical
    if slow is not None and len(slow.sigma):
        ax.plot(slow.sigma, slow.Abar_b, "k--", lw=1.4, label=r"slow flow $\bar A_b$ (46)")
    rows = list(critical_rows(chart, points=201))
    ax.plot([r["sigma"] for r in rows], [r["Abar_c_full"] for r in rows], "-", color="tab:green", lw=3, alpha=0.6, label=r"full model $\bar A_c$ (9)")
    ax.plot([], [], "k*", label="codimension-2 point")
    ax.plot([], [], "k:", label="curve not bounding stable orbits")
    ax.set_xlim(*chart.sigma_range)
    ax.set_ylim(*chart.abar_range)
    ax.set_xlabel(r"detuning $\sigma$")
    ax.set_ylabel(r"forcing $\bar A$")
    P = chart.params
    partial = "" if chart.status == "complete" else f"\nPARTIAL: {chart.status}"
    ax.set_title(f"Orbit bifurcations of (9) in (sigma, Abar): eps = {P.eps:g}, beta = {P.beta:g}, gamma = {P.gamma:g}, n = {P.n}{partial}")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    return save_figure(fig, path)
