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

from slosh_bif.orbits.codim2 import CODIM2_KINDS, BifurcationCurve, curve_boundary
from slosh_bif.report.files import DAMAGE, damaged, read_store, write_text_atomically
from slosh_bif.report.tables import write_rows
from slosh_bif.studies.chart.critical import CRITICAL_COLUMNS, critical_rows
from slosh_bif.studies.chart.reading import critical_at, lowest_stable_boundary, variant_of

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
    "coefficient",
    "boundary",
    "status",
    "origin",
)


def curve_columns(second: str = "Abar") -> tuple:
    """The columns of ``curves.csv`` for a chart in (sigma, ``second``)."""
    return tuple(second if name == "Abar" else name for name in CURVE_COLUMNS)


def curve_rows(chart):
    for k, c in enumerate(chart.curves):
        labels = c.branch.special_labels()
        coefficient, kinds = curve_boundary(c)
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
                "coefficient": float(coefficient[i]),
                "boundary": kinds[i],
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
            "coefficient": np.nan,
            "boundary": "",
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


# one colour a kind (none of them the regime map's red, green or blue) and one line style a way of
# losing stability: solid soft, dashed a jump (a hard PD, NS or BP, or a fold), dotted undetermined
_COLORS = {"LP": "black", "PD": "tab:cyan", "NS": "tab:purple", "BP": "tab:orange", "GR": "tab:brown"}
_KIND_NAMES = {
    "LP": "LP (fold)",
    "PD": "PD (period doubling)",
    "NS": "NS (torus)",
    "BP": "BP (symmetry breaking)",
}
_LOSS_STYLES = {
    "soft": ("-", "solid: lost softly (a small new motion grows)"),
    "jump": ((0, (5, 2)), "dashed: a jump (a fold, or a hard PD, NS or BP)"),
    "undetermined": ((0, (1, 1.5)), "dotted: undetermined (near a codimension-2 point, or unsettled)"),
    "unknown": ("-", "solid on a PD, NS or BP curve without its coefficient: soft or hard not computed"),
}


def _loss_style(kinds) -> np.ndarray:
    """Each point's style key: hard and jump are both a jump, none (a contact crossing) soft; ''
    (no coefficient: a curve traced without the map's derivatives, such as one from an earlier
    run) unknown."""
    out = np.asarray(kinds, dtype="<U12").copy()
    out[out == "hard"] = "jump"
    out[out == "none"] = "soft"  # a contact crossing: the stable response starts to touch the walls
    out[out == ""] = "unknown"
    return out


def _primary(chart) -> str:
    """The name of the chart's primary orbit branch (the one its curves start from first)."""
    return chart.family.branches[0].name if chart.family is not None and chart.family.branches else ""


def _draw(ax, chart, *, numbers: bool):
    """On ``ax``: the stable region's lower boundary Abar_c of the full model on top, styled by how
    stability is lost along it; each curve where it bounds stable orbits in its kind's colour and
    its loss's style (the primary family's bold, the other families' thin); where it does not,
    faint; the slow flow's Abar_b; the codimension-2 points (numbered in the zoom, clear of each
    other). Returns {legend label: handle} of what was drawn."""
    from matplotlib.lines import Line2D

    from slosh_bif.report.plotting import place_labels

    drawn, kinds_drawn, styles_drawn = {}, [], set()
    primary = f"on the {_primary(chart)} branch"
    for c in chart.curves:
        main = primary in c.origin
        s, a, st = c["sigma"], c[chart.second], c.branch.stable
        color = _COLORS[c.kind]
        if c.kind == "GR":  # where the number of impacts changes: one style, stable or not
            (line,) = ax.plot(s, a, "-.", color=color, lw=1.1, alpha=0.8)
            drawn.setdefault("GR (grazing: the number of impacts changes)", line)
            continue
        ax.plot(s, np.where(st, np.nan, a), "-", color=color, lw=0.6, alpha=0.18)
        loss = _loss_style(curve_boundary(c)[1])
        for key, (style, _) in _LOSS_STYLES.items():
            mask = st & (loss == key)
            if np.any(mask):
                ax.plot(
                    s,
                    np.where(mask, a, np.nan),
                    linestyle=style,
                    color=color,
                    lw=1.9 if main else 0.7,
                    alpha=1.0 if main else 0.35,
                )
                styles_drawn.add(key)
        if np.any(st) and c.kind not in kinds_drawn:
            kinds_drawn.append(c.kind)
    for kind in sorted(kinds_drawn, key=list(_KIND_NAMES).index):
        drawn[_KIND_NAMES[kind]] = Line2D([], [], color=_COLORS[kind], lw=2)
    for key, (style, label) in _LOSS_STYLES.items():
        if key in styles_drawn:
            drawn[label] = Line2D([], [], color="0.3", lw=1.6, linestyle=style)
    drawn["faint: bounding unstable orbits (bold: the primary family)"] = Line2D(
        [], [], color="0.5", lw=0.8, alpha=0.4
    )
    _draw_critical(ax, chart, drawn)
    rows = list(codim2_rows(chart))
    if rows:
        points = [(r["sigma"], r[chart.second]) for r in rows]
        (stars,) = ax.plot(*zip(*points), "*", color="k", mec="w", mew=0.4, ms=7, zorder=6)
        drawn["codimension-2 point (numbered; codim2.csv)"] = stars
        if numbers:  # a number with no free side is left to codim2.csv
            place_labels(
                ax,
                [(x, y, str(r["number"]), "k") for (x, y), r in zip(points, rows)],
                markers=points,
                sides=((4, 4), (4, -11), (-16, 4), (-16, -11)),
            )
    return drawn


def _draw_critical(ax, chart, drawn):
    """The two critical forcings: the slow flow's Abar_b (thin black dash-dot: a fold of (46), a
    jump) and the full model's Abar_c, thick green, solid where it is lost softly, dashed where
    by a jump."""
    slow = chart.slow_flow_critical
    if slow is not None and len(slow.sigma):
        (line,) = ax.plot(slow.sigma, slow.Abar_b, "k-.", lw=1.3, zorder=5)
        drawn[r"slow flow $\bar A_b$ " + ("(46)" if slow.model == "slowflow" else "(corrected)")] = line
    if not chart.reads_critical:
        return
    grid = np.linspace(*chart.sigma_range, 401)
    low = chart.abar_range[0]
    sides = {}
    variant = variant_of(chart) or "paper"
    found = [
        critical_at(
            chart.curves,
            g,
            chart.params,
            low,
            corrected=False,
            sides=sides,
            variant=variant,
            bottom=chart.bottom,
        )
        for g in grid
    ]
    full = np.array([f[0] for f in found])
    if not np.any(np.isfinite(full)):
        return
    loss = _loss_style([f[2] for f in found])
    label = rf"full model $\bar A_c$ {chart.orbits}: least forcing with a stable periodic response lost"
    for key, (style, _) in _LOSS_STYLES.items():
        mask = loss == key
        # each stretch joined to its neighbours, so that a change of style leaves no gap
        joined = mask | np.roll(mask, 1) & np.r_[False, np.ones(len(mask) - 1, bool)]
        if np.any(mask):
            (line,) = ax.plot(
                grid,
                np.where(joined, full, np.nan),
                linestyle=style,
                color="tab:green",
                lw=3.2,
                alpha=0.85,
                zorder=4,
            )
            drawn.setdefault(label, line)


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
    """The chart in full and, for a (sigma, Abar) chart, a zoom on the resonance region: the full
    model's critical forcing on top, the curves in their kinds' colours and their losses' styles
    (soft solid, a jump dashed; the primary family's bold, the other families' thin, stretches
    bounding unstable orbits faint), the slow flow's critical forcing, numbered codimension-2
    points (their table in ``codim2.csv``), and the regime map behind them when given."""
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
        ncol=3,
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
