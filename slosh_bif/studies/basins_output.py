"""A basin map as files: ``basins.csv`` (one row per initial state: the two state components and
the attractor reached), ``attractors.txt`` (each attractor described, and its share of the
plane), ``basins.png`` (the plane coloured by attractor) and ``basins.json`` (every simulated
cell at full precision, stored as cells finish: what ``basins --resume`` reads)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from slosh_bif.report.files import CellStore, write_text_atomically
from slosh_bif.report.tables import write_rows

__all__ = [
    "write_basins_csv",
    "write_attractors",
    "attractor_table",
    "plot_basins",
    "basin_settings",
    "basin_store",
]


def write_basins_csv(bmap, path) -> Path:
    """One row per initial state: the attractor, whether a perturbed copy reached another
    (``uncertain``), and the forcing periods its strobe took to settle (empty: not settled)."""
    a, b = bmap.axes
    rows = (
        {
            a: float(x),
            b: float(y),
            "attractor": bmap.label[i, j],
            "uncertain": int(bmap.uncertain[i, j]),
            "periods_to_settle": bmap.periods[i, j],
        }
        for i, y in enumerate(bmap.second)
        for j, x in enumerate(bmap.first)
    )
    return write_rows(rows, (a, b, "attractor", "uncertain", "periods_to_settle"), path)


def attractor_table(bmap) -> str:
    """Each attractor's share of the plane with its bounds at this resolution, what it is, and how
    far the cell-by-cell picture can be believed."""
    P = bmap.params
    lines = [
        f"basins at sigma = {P.sigma:g}, Abar = {P.Abar:g} over ({bmap.axes[0]}, {bmap.axes[1]}), "
        f"each start followed until its strobe settles (tau up to {bmap.tmax:.6g}): {bmap.status}"
    ]
    for name, (low, high) in bmap.fraction_bounds().items():
        lines.append(
            f"{100 * low:5.1f} - {100 * high:5.1f} %  {name}"
            + (f": {bmap.attractors[name]}" if name in bmap.attractors else "")
        )
    f = bmap.uncertain_fraction
    if f:
        sizes = ", ".join(
            f"{100 * share:.1f} % at eps = {eps:g}" for eps, share in sorted(f.items(), reverse=True)
        )
        lines.append(
            "uncertain cells (a start moved by eps times the plane's width reaches another "
            f"attractor): {sizes}"
        )
        alpha, transient = bmap.uncertainty_exponent, bmap.transient_uncertain
        if math.isfinite(alpha) and transient:
            lines.append(
                f"uncertainty exponent not judged: {transient} of the {int(np.sum(bmap.uncertain))} "
                f"uncertain cells had a start that did not settle by tau = {bmap.tmax:.6g}, whose "
                "label is a transient's regime, not an attractor (a longer --tmax may settle them)"
            )
        elif math.isfinite(alpha):
            verdict = (
                "smooth basin boundaries"
                if alpha > 0.8
                else "fractal basin boundaries: which attractor a given start reaches is decided by "
                "digits no integration keeps; only the bounds on the shares mean anything"
                if alpha < 0.2
                else "partly fractal basin boundaries"
            )
            lines.append(
                f"uncertainty exponent alpha = {max(alpha, 0.0):.2f} (f ~ eps^alpha, from the two "
                f"sizes): {verdict}"
            )
    settled = bmap.periods[np.isfinite(bmap.periods)]
    if settled.size:
        lines.append(
            f"strobes settled after {int(np.median(settled))} periods (median), "
            f"{int(settled.max())} at most; {int(np.sum(~np.isfinite(bmap.periods)))} cells did "
            "not settle"
        )
    return "\n".join(lines)


def write_attractors(bmap, path) -> Path:
    return write_text_atomically(path, attractor_table(bmap) + "\n")


def plot_basins(bmap, path) -> Path:
    """The plane coloured by attractor, uncertain cells hatched; the legend gives each basin's share
    bounds."""
    from matplotlib.colors import ListedColormap

    from slosh_bif.report.plotting import cell_edges, pyplot, save_figure

    names = list(bmap.fractions())
    codes = np.vectorize(names.index)(bmap.label).astype(float)
    colors = [pyplot().get_cmap("tab10")(k % 10) for k in range(len(names))]

    fig, ax = pyplot().subplots(figsize=(9.5, 6))
    xe, ye = cell_edges(bmap.first), cell_edges(bmap.second)
    ax.pcolormesh(xe, ye, codes, cmap=ListedColormap(colors), vmin=-0.5, vmax=len(names) - 0.5)
    if np.any(bmap.uncertain):
        ax.pcolormesh(
            xe,
            ye,
            np.ma.masked_where(~bmap.uncertain, np.ones(bmap.uncertain.shape)),
            cmap=ListedColormap(["white"]),
            alpha=0.55,
        )
    bounds = bmap.fraction_bounds()
    for name, color in zip(names, colors):
        low, high = bounds[name]
        ax.plot([], [], "s", color=color, ms=9, label=f"{name} ({100 * low:.0f}-{100 * high:.0f} %)")
    if np.any(bmap.uncertain):
        ax.plot([], [], "s", color="0.85", ms=9, label="pale: uncertain (a nearby start ends elsewhere)")
    ax.set_xlabel(f"initial {bmap.axes[0]}")
    ax.set_ylabel(f"initial {bmap.axes[1]}")
    P = bmap.params
    alpha = bmap.uncertainty_exponent
    judged = math.isfinite(alpha) and not bmap.transient_uncertain
    note = f"; uncertainty exponent {max(alpha, 0.0):.2f}" if judged else ""
    ax.set_title(
        f"basins of attraction of {'(8)' if bmap.model == 'impact' else '(9)'}: sigma = {P.sigma:g}, "
        f"Abar = {P.Abar:g}, n = {P.n}{note}"
        + ("" if bmap.status == "complete" else f"\nPARTIAL: {bmap.status}"),
        fontsize=10,
    )
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return save_figure(fig, path)


def basin_settings(params, axes, first, second, tmax, model: str = "smooth") -> dict:
    """What decides every cell of a basin map (a resumed run reuses stored cells only when equal)."""
    from slosh_bif.studies.basins import PERTURBATIONS, SETTLE_PERIODS, SETTLE_TOL

    return {
        "params": params.as_dict(),
        "axes": list(axes),
        "first": [float(v) for v in first],
        "second": [float(v) for v in second],
        "tmax": float(tmax),
        "settle": [SETTLE_TOL, SETTLE_PERIODS],
        "perturbations": list(PERTURBATIONS),
        **({"model": model} if model != "smooth" else {}),  # stores of (9) written without it resume
    }


def basin_store(path, settings: dict, *, resume: bool) -> CellStore:
    """The cells of :func:`~slosh_bif.studies.basins.basin_map` (each start's and its perturbed
    copies' outcome, orbit state at tau = 0 or None, and periods), stored as they finish (see
    :class:`~slosh_bif.report.files.CellStore`)."""

    def encode(result):
        return [
            [outcome, None if y0 is None else [float(v) for v in y0], int(periods)]
            for outcome, y0, periods in result
        ]

    def decode(record):
        return [
            (str(outcome), None if y0 is None else np.asarray(y0, dtype=float), int(periods))
            for outcome, y0, periods in record
        ]

    return CellStore(path, settings, resume=resume, encode=encode, decode=decode)
