"""A basin map as files: ``basins.csv`` (one row per initial state: the two state components and
the attractor reached), ``attractors.txt`` (each attractor described, and its share of the
plane), ``basins.png`` (the plane coloured by attractor) and ``basins.json`` (every simulated
cell at full precision, stored as cells finish: what ``basins --resume`` reads)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.report.files import CellStore, write_text_atomically
from slosh_bif.report.tables import write_rows

__all__ = ["write_basins_csv", "write_attractors", "attractor_table", "plot_basins", "basin_settings", "basin_store"]


def write_basins_csv(bmap, path) -> Path:
    a, b = bmap.axes
    rows = ({a: float(x), b: float(y), "attractor": bmap.label[i, j]} for i, y in enumerate(bmap.second) for j, x in enumerate(bmap.first))
    return write_rows(rows, (a, b, "attractor"), path)


def attractor_table(bmap) -> str:
    """One line per attractor: its share of the plane and what it is."""
    lines = [f"basins at sigma = {bmap.params.sigma:g}, Abar = {bmap.params.Abar:g} over ({bmap.axes[0]}, {bmap.axes[1]}), tau up to {bmap.tmax:.6g}: {bmap.status}"]
    for name, share in bmap.fractions().items():
        lines.append(f"{100 * share:5.1f} %  {name}" + (f": {bmap.attractors[name]}" if name in bmap.attractors else ""))
    return "\n".join(lines)


def write_attractors(bmap, path) -> Path:
    return write_text_atomically(path, attractor_table(bmap) + "\n")


def plot_basins(bmap, path) -> Path:
    from matplotlib.colors import ListedColormap

    from slosh_bif.report.plotting import cell_edges, pyplot, save_figure

    names = list(bmap.fractions())
    codes = np.vectorize(names.index)(bmap.label).astype(float)
    colors = [pyplot().get_cmap("tab10")(k % 10) for k in range(len(names))]

    fig, ax = pyplot().subplots(figsize=(8.5, 6))
    ax.pcolormesh(cell_edges(bmap.first), cell_edges(bmap.second), codes, cmap=ListedColormap(colors), vmin=-0.5, vmax=len(names) - 0.5)
    for name, color, share in zip(names, colors, bmap.fractions().values()):
        ax.plot([], [], "s", color=color, ms=9, label=f"{name} ({100 * share:.0f} %)")
    ax.set_xlabel(f"initial {bmap.axes[0]}")
    ax.set_ylabel(f"initial {bmap.axes[1]}")
    P = bmap.params
    ax.set_title(f"basins of attraction of (9): sigma = {P.sigma:g}, Abar = {P.Abar:g}, n = {P.n}" + ("" if bmap.status == "complete" else f"\nPARTIAL: {bmap.status}"), fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return save_figure(fig, path)


def basin_settings(params, axes, first, second, tmax) -> dict:
    """What decides every cell of a basin map (a resumed run reuses stored cells only when equal)."""
    return {"params": params.as_dict(), "axes": list(axes), "first": [float(v) for v in first], "second": [float(v) for v in second], "tmax": float(tmax)}


def basin_store(path, settings: dict, *, resume: bool) -> CellStore:
    """The cells of :func:`~slosh_bif.studies.basins.basin_map`, (regime, orbit state at tau = 0
    or None), stored as they finish (see :class:`~slosh_bif.report.files.CellStore`)."""

    def encode(result):
        regime, y0 = result
        return [regime, None if y0 is None else [float(v) for v in y0]]

    def decode(record):
        return record[0], None if record[1] is None else np.asarray(record[1], dtype=float)

    return CellStore(path, settings, resume=resume, encode=encode, decode=decode)
