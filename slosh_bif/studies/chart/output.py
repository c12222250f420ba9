"""The chart as files: ``curves.csv`` (one row per curve point, in curve order), ``critical.csv``
(Abar_b of (46) against Abar_c of (9) on a sigma grid), ``codim2.csv`` (the codimension-2 points,
numbered as on the picture), ``chart.png``, and the curve store
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
from slosh_bif.studies.chart.critical import CRITICAL_COLUMNS, critical_rows, lowest_stable_boundary

__all__ = [
    "CURVE_COLUMNS",
    "curve_rows",
    "write_curves_csv",
    "write_critical_csv",
    "write_codim2_csv",
    "codim2_rows",
    "plot_chart",
    "chart_settings",
    "curve_store",
    "curve_columns",
]

CURVE_COLUMNS = (
    "curve",
    "kind",
    "sigma",
    "Abar",
    "A1",
    "max_abs_w",
    "codim2",
    "bounds_stable",
    "status",
    "origin",
)


def curve_columns(second: str = "Abar") -> tuple:
    """The columns of ``curves.csv`` for a chart in (sigma, ``second``)."""
    return tuple(second if name == "Abar" else name for name in CURVE_COLUMNS)


def curve_rows(chart):
    for k, c in enumerate(chart.curves):
        labels = c.branch.special_labels()
        for i in range(len(c)):
            yield {
                "curve": k,
                "kind": c.kind,
                "sigma": float(c["sigma"][i]),
                chart.second: float(c[chart.second][i]),
                "A1": float(c["A1"][i]),
                "max_abs_w": float(c["max_abs_w"][i]),
                "codim2": labels[i] if labels[i] in CODIM2_KINDS else "",
                "bounds_stable": int(c.branch.stable[i]),
                "status": c.status,
                "origin": c.origin,
            }
    for k, f in enumerate(
        chart.failures, start=len(chart.curves)
    ):  # a start that gave no curve: one row at the start point
        yield {
            "curve": k,
            "kind": f.kind,
            "sigma": f.sigma,
            chart.second: f.value,
            "A1": np.nan,
            "max_abs_w": np.nan,
            "codim2": "",
            "bounds_stable": "",
            "status": f"failed to start: {f.reason}",
            "origin": f.origin,
        }


def write_curves_csv(chart, path) -> Path:
    return write_rows(curve_rows(chart), curve_columns(chart.second), path)


def write_critical_csv(chart, path) -> Path:
    return write_rows(critical_rows(chart), CRITICAL_COLUMNS, path)


CODIM2_COLUMNS = ("number", "label", "sigma", "Abar", "curve", "kind")


def codim2_rows(chart):
    """The codimension-2 points in curve order, numbered as on ``chart.png``."""
    number = 0
    for k, c in enumerate(chart.curves):
        for label, sigma, value in c.codim2_points():
            number += 1
            yield {
                "number": number,
                "label": label,
                "sigma": sigma,
                chart.second: value,
                "curve": k,
                "kind": c.kind,
            }


def write_codim2_csv(chart, path) -> Path:
    return write_rows(
        codim2_rows(chart), tuple(chart.second if c == "Abar" else c for c in CODIM2_COLUMNS), path
    )


_COLORS = {"LP": "tab:red", "PD": "tab:blue", "NS": "tab:purple", "BP": "tab:orange", "GR": "tab:brown"}


def _primary(chart) -> str:
    """The name of the chart's primary orbit branch (the one its curves start from first)."""
    return chart.family.branches[0].name if chart.family is not None and chart.family.branches else ""


def _draw(ax, chart, *, numbers: bool):
    """The curves (the primary family's bold, the other families' faint; solid where they bound
    stable orbits), the two critical forcings and the numbered codimension-2 points on ``ax``;
    returns {legend label: handle} of what was drawn."""
    from slosh_bif.report.plotting import place_labels

    drawn = {}
    primary = f"on the {_primary(chart)} branch"
    for c in chart.curves:
        main = primary in c.origin
        s, a, st = c["sigma"], c[chart.second], c.branch.stable
        style = dict(color=_COLORS[c.kind], lw=1.8 if main else 0.8, alpha=1.0 if main else 0.45)
        if c.kind == "GR":  # where the number of impacts changes: one style, stable or not
            (line,) = ax.plot(s, a, "-.", **{**style, "lw": 1.2})
            drawn.setdefault("GR curve (grazing: the number of impacts changes)", line)
            continue
        (line,) = ax.plot(s, np.where(st, a, np.nan), "-", **style)
        if np.any(st):
            drawn.setdefault(f"{c.kind} curve" + ("" if main else " (other families)"), line)
        if np.any(~st):
            (dotted,) = ax.plot(s, np.where(st, np.nan, a), ":", **{**style, "lw": style["lw"] * 0.7})
            drawn.setdefault("curve not bounding stable orbits (dotted)", dotted)
    slow = chart.slow_flow_critical
    if slow is not None and len(slow.sigma):
        (line,) = ax.plot(slow.sigma, slow.Abar_b, "k--", lw=1.6)
        drawn[r"slow flow $\bar A_b$ " + ("(46)" if slow.model == "slowflow" else "(corrected)")] = line
    if chart.second == "Abar":
        grid = np.linspace(*chart.sigma_range, 401)
        full = np.array([lowest_stable_boundary(chart.curves, sigma)[0] for sigma in grid])
        if np.any(np.isfinite(full)):
            (line,) = ax.plot(grid, full, "-", color="tab:green", lw=4, alpha=0.55, zorder=1)
            drawn[rf"full model $\bar A_c$ {chart.orbits}: least stable periodic response"] = line
    rows = list(codim2_rows(chart))
    if rows:
        (stars,) = ax.plot([r["sigma"] for r in rows], [r[chart.second] for r in rows], "k*", ms=7, zorder=5)
        drawn["codimension-2 point (numbered; codim2.csv)"] = stars
        if numbers:  # a number that would overlap one already placed is left to codim2.csv
            place_labels(ax, [(r["sigma"], r[chart.second], str(r["number"]), "k") for r in rows])
    return drawn


def _zoom_box(chart):
    """The resonance region: sigma around 0 (the 1:1 resonance of the scaled model), a fifth of
    the box wide, and Abar up to two and a half times the slow flow's critical forcing there
    (the full model's where the slow flow has none); None when the box does not reach it."""
    (s0, s1), (a0, a1) = chart.sigma_range, chart.abar_range
    half = 0.1 * (s1 - s0)
    lo, hi = max(s0, -half), min(s1, half)
    if not lo < hi:
        return None
    grid = np.linspace(lo, hi, 41)
    slow = chart.slow_flow_critical
    depth = (
        np.interp(grid, slow.sigma, slow.Abar_b)
        if slow is not None and len(slow.sigma)
        else np.array([lowest_stable_boundary(chart.curves, g)[0] for g in grid])
    )
    top = 2.5 * float(np.nanmax(depth)) if np.any(np.isfinite(depth)) else a1
    return (lo, hi), (a0, min(a1, max(top, a0 + 0.1 * (a1 - a0))))


def plot_chart(chart, path, *, regimes=None) -> Path:
    """The chart in full and, for a (sigma, Abar) chart, a zoom on the resonance region; the
    primary family's curves bold and the other families' faint, the critical forcings of both
    models, numbered codimension-2 points (their table in ``codim2.csv``), and the regime map
    behind them when given."""
    from slosh_bif.report.plotting import pyplot, save_figure

    box = _zoom_box(chart) if chart.second == "Abar" else None
    fig, axes = pyplot().subplots(
        1,
        2 if box else 1,
        figsize=(16, 6.5) if box else (11.5, 6.5),
        gridspec_kw={"width_ratios": [1.6, 1]} if box else None,
        squeeze=False,
    )
    panels = [(axes[0][0], chart.sigma_range, chart.abar_range)] + ([(axes[0][1], *box)] if box else [])
    drawn = {}
    for ax, xlim, ylim in panels:
        if regimes is not None:
            from slosh_bif.simulation.output import draw_regimes

            draw_regimes(ax, regimes, alpha=0.35)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        drawn.update(_draw(ax, chart, numbers=ax is not panels[0][0] or box is None))
        ax.set_xlabel(r"detuning $\sigma$")
        ax.set_ylabel(r"forcing $\bar A$" if chart.second == "Abar" else chart.second)
        ax.grid(alpha=0.3)
    if box:
        axes[0][1].set_title("the resonance region (numbers: codim2.csv)", fontsize=9)
        axes[0][0].indicate_inset(
            (box[0][0], box[1][0], box[0][1] - box[0][0], box[1][1] - box[1][0]), edgecolor="0.3"
        )
    P = chart.params
    partial = "" if chart.status == "complete" else f"\nPARTIAL: {chart.status}"
    held = ", ".join(
        f"{name} = {getattr(P, name):g}"
        for name in ("eps", "beta", "gamma", "Abar", "n")
        if name != chart.second
    )
    axes[0][0].set_title(
        f"Orbit bifurcations of {chart.orbits} in (sigma, {chart.second}): {held}{partial}", fontsize=10
    )
    regime_handles, regime_labels = axes[0][
        0
    ].get_legend_handles_labels()  # the regime map's entries, if drawn
    fig.legend(
        regime_handles + list(drawn.values()),
        regime_labels + list(drawn),
        fontsize=8,
        loc="lower center",
        ncol=4,
        frameon=False,
        bbox_to_anchor=(0.5, 0.0),
    )
    fig.tight_layout(rect=(0, 0.13, 1, 1))
    return save_figure(fig, path)


def chart_settings(params, state0, sigma_range, abar_range, **options) -> dict:
    """What decides the chart's starts and curves: a resumed run reuses stored curves only when
    these are equal."""
    return {
        "params": params.as_dict(),
        "state0": [float(v) for v in state0],
        "sigma_range": [float(v) for v in sigma_range],
        "abar_range": [float(v) for v in abar_range],
        **options,
    }


def curve_store(folder, settings: dict, *, resume: bool):
    """(done, keep) for :func:`~slosh_bif.studies.chart.smooth.bifurcation_chart`: the curves stored in
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
