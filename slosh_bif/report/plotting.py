"""All matplotlib lives here: the manifold (36) with trajectories projected on it, time histories.

Functions draw on an ``Axes`` they are given and return it, so callers compose figures freely.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.model import manifold
from slosh_bif.report.files import replaced_atomically

__all__ = [
    "plot_manifold",
    "plot_slow_manifold",
    "plot_projection",
    "plot_time_history",
    "plot_branch",
    "branch_legend",
    "drawn",
    "mark_special",
    "stability_runs",
    "pyplot",
    "save_figure",
    "cell_edges",
]


def pyplot():
    """matplotlib.pyplot on the file-only Agg backend (no display needed on a server or in CI)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path, *, dpi=130, layout=True) -> Path:
    """Lay out (unless the figure has its own layout engine, or ``layout`` is False: its caller
    placed the axes), write and close ``fig``; returns the path."""
    if layout and fig.get_layout_engine() is None:
        fig.tight_layout()
    with replaced_atomically(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    pyplot().close(fig)
    return Path(path)


def plot_manifold(ax, rho, A_max=None, *, color="tab:blue", label="SIM"):
    """Both branches of the slow invariant manifold (36) in the (A, alpha) plane: S+ solid, S- dashed."""
    A_end = float(manifold.a_min(rho))
    A_max = A_max if A_max is not None else max(3.0, 3 * A_end)
    # Cluster points at the fold, where alpha has a square-root singularity.
    A = A_end + (A_max - A_end) * np.linspace(0, 1, 400) ** 2
    return _draw_manifold(
        ax,
        A,
        manifold.alpha(A, rho, manifold.STABLE),
        manifold.alpha(A, rho, manifold.UNSTABLE),
        color,
        label,
    )


def plot_slow_manifold(ax, law, A_max, *, color="tab:blue", label="SIM"):
    """Both branches of (36) for a parameter set (``law`` a :class:`~slosh_bif.model.ManifoldLaw`), rho(A)
    from (39) when pbar != 0."""
    A, stable, unstable = law.branches(A_max)
    return _draw_manifold(ax, A, stable, unstable, color, label)


def _draw_manifold(ax, A, stable, unstable, color, label):
    ax.plot(A, stable, "-", color=color, label=f"{label} stable branch")
    ax.plot(A, unstable, "--", color=color, label=f"{label} unstable branch")
    ax.plot([A[0]], [stable[0]], "o", color=color, ms=4)  # the fold (A_min, alpha_min)
    ax.set_xlabel("amplitude A of X")
    ax.set_ylabel(r"triangle-wave amplitude $\alpha$")
    return ax


def plot_projection(ax, projection, *, label="simulation"):
    """A trajectory projected on the manifold's plane: red dots joined by a thin black line."""
    ax.plot(projection.A, projection.alpha, "-", color="k", lw=0.5)
    ax.plot(projection.A, projection.alpha, ".", color="tab:red", ms=4, label=label)
    return ax


def plot_time_history(ax, t, y, *, envelope=None):
    """X (blue) and w (red) against tau; optionally a slow-flow envelope ``(tau, A)`` in black."""
    ax.plot(t, y[2], color="tab:red", lw=0.6, label="w")
    ax.plot(t, y[0], color="tab:blue", lw=0.6, label="X")  # on top: w's fast motion would hide it
    if envelope is not None:
        ax.plot(envelope[0], envelope[1], color="k", lw=1.5, label="slow flow A")
        ax.plot(envelope[0], -np.asarray(envelope[1]), color="k", lw=1.5)
    ax.set_xlabel(r"$\tau$")
    return ax


def stability_runs(mask):
    """(start, stop) index pairs of the runs of equal values in a boolean array (stop inclusive:
    each run drawn as one line reaches the next run's first point)."""
    change = np.flatnonzero(np.diff(mask.astype(int))) + 1
    bounds = np.concatenate([[0], change, [len(mask)]])
    return [(a, min(b, len(mask) - 1)) for a, b in zip(bounds[:-1], bounds[1:])]


SPECIAL_MARKERS = {
    "LP": ("o", "tab:red"),
    "BP": ("s", "tab:green"),
    "PD": ("D", "tab:purple"),
    "NS": ("^", "tab:orange"),
    "GR": ("*", "tab:brown"),
    "END": ("x", "k"),
}
SPECIAL_NAMES = {
    "LP": "fold (LP)",
    "BP": "branch point (BP)",
    "PD": "period doubling (PD)",
    "NS": "Neimark-Sacker (NS)",
    "GR": "grazing (GR)",
    "END": "end",
}


MERGE_POINTS = 5.0  # display points: markers of one kind nearer than this are drawn as one, counted


def special_legend(ax, kinds):
    """Legend entries for the special-point markers of ``kinds`` (in the markers' order)."""
    for kind in (k for k in SPECIAL_MARKERS if k in kinds):
        marker, color = SPECIAL_MARKERS[kind]
        ax.plot(
            [],
            [],
            marker,
            color=color,
            mfc="none" if kind == "LP" else color,
            ls="none",
            label=SPECIAL_NAMES[kind],
        )


def branch_legend(ax, *, stable: bool, unstable: bool, kinds=()):
    """Legend entries for what a figure of branches draws, and nothing else: "stable" (solid)
    and "unstable" (dashed) where such runs are drawn, and the special points' kinds marked."""
    if stable:
        ax.plot([], [], "k-", label="stable")
    if unstable:
        ax.plot([], [], "k--", label="unstable")
    special_legend(ax, kinds)


def drawn(branches) -> dict:
    """What :func:`plot_branch` draws of ``branches``, as :func:`branch_legend`'s keywords."""
    branches = list(branches)
    return {
        "stable": any(np.any(b.stable) for b in branches if len(b)),
        "unstable": any(not np.all(b.stable) for b in branches if len(b)),
        "kinds": {s.kind for b in branches for s in b.special},
    }


def mark_special(ax, points, *, annotate=True, label_ends=True, ms=6):
    """Markers of special points ``(x, y, kind)``: points of one kind closer than
    :data:`MERGE_POINTS` on the axes are drawn as one marker whose label counts them ("NS ×3"),
    so that a marker never hides another of its kind; labels placed without collisions."""
    ax.get_xlim(), ax.get_ylim()  # the limits so far, so that display positions are right
    groups = []  # [kind, u, v, x, y, count]
    for x, y, kind in points:
        u, v = ax.transData.transform((x, y))
        for group in groups:
            if group[0] == kind and abs(group[1] - u) < MERGE_POINTS and abs(group[2] - v) < MERGE_POINTS:
                group[5] += 1
                break
        else:
            groups.append([kind, u, v, x, y, 1])
    labels = []
    for kind, _, _, x, y, count in groups:
        marker, color = SPECIAL_MARKERS[kind]
        ax.plot(x, y, marker, color=color, ms=ms, mfc="none" if kind == "LP" else color)
        if annotate and (kind != "END" or label_ends):
            labels.append((x, y, kind if count == 1 else f"{kind} \u00d7{count}", color))
    place_labels(ax, labels)


def plot_branch(ax, branch, y, *, x=None, color="tab:blue", label=None, label_ends=True, annotate=True):
    """A branch: stable runs solid, unstable dashed, special points marked and labelled
    (:func:`mark_special`).

    ``y`` (and optionally ``x``, default the continued parameter) are arrays along the branch.
    """
    x = branch.p if x is None else x
    for a, b in stability_runs(branch.stable):
        ax.plot(x[a : b + 1], y[a : b + 1], "-" if branch.stable[a] else "--", color=color, lw=1.4)
    if label is not None:  # the branch's legend entry in its colour, solid: dashes mean unstable only
        ax.plot([], [], "-", color=color, lw=1.4, label=label)
    points = [(x[s.index], y[s.index], s.kind) for s in branch.special]
    mark_special(ax, points, annotate=annotate, label_ends=label_ends)
    return ax


def place_labels(ax, items, *, apart=(18, 10), markers=(), sides=((4, 4),)):
    """Annotate each (x, y, text, color) of ``items`` beside its point, on the first of ``sides``
    (offsets in points) where the label lands at least ``apart`` display units from every label
    already on ``ax`` and, when ``markers`` ((x, y) in data) are given, clear of the other
    markers; a label with no free side is skipped (its marker still shows; tables and legends
    carry the rest)."""
    if not items:
        return
    # the final (autoscaled) limits, so that display positions are right: reading them updates
    # transData without drawing the figure (a whole draw per branch would be most of a family's plot)
    ax.get_xlim(), ax.get_ylim()
    scale = ax.figure.dpi / 72.0  # display units per point
    placed = [tuple(ax.transData.transform(t.xy)) for t in ax.texts if hasattr(t, "xy")]  # earlier calls'
    dots = [tuple(ax.transData.transform(m)) for m in markers]
    for x, y, text, color in items:
        u, v = ax.transData.transform((x, y))
        if not ax.bbox.contains(u, v):
            continue
        for dx, dy in sides:
            # where the label sits, measured from the first side's place (the point itself there)
            cu, cv = u + (dx - sides[0][0]) * scale, v + (dy - sides[0][1]) * scale
            free = all(abs(cu - p) > apart[0] or abs(cv - q) > apart[1] for p, q in placed)
            clear = all(
                abs(cu + 6 * scale - p) > 9 * scale or abs(cv + 6 * scale - q) > 7 * scale
                for p, q in dots
                if (p, q) != (u, v)
            )
            if free and clear:
                ax.annotate(
                    text, (x, y), textcoords="offset points", xytext=(dx, dy), fontsize=8, color=color
                )
                placed.append((cu, cv))
                break


def cell_edges(v) -> np.ndarray:
    """Edges of the cells centred on the grid values ``v`` (for ``pcolormesh``)."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])
