"""The trust map of :mod:`slosh_bif.studies.trust` as ``trust_map.csv``, ``trust_map.png`` and a text
table."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np

from slosh_bif.report.files import DAMAGE, damaged, read_store, write_text_atomically
from slosh_bif.report.tables import write_rows
from slosh_bif.studies.trust import TRUST_COLUMNS, TrustPoint

__all__ = ["write_trust_csv", "trust_table", "plot_trust_map", "trust_store"]


def write_trust_csv(points, path) -> Path:
    return write_rows([p.as_row() for p in points], TRUST_COLUMNS, path, digits=6)


def _percent(value) -> str:
    return "  -" if not np.isfinite(value) else f"{100 * value:3.0f}"


_MODEL_NAMES = {
    "slowflow": "slow flow (46) as derived",
    "corrected": "corrected slow flow (the wall's kappa and clearance)",
}


_IMPACT_TAGS = {"paper": "(8)", "corrected": "(C)"}  # (C): the corrected impact model


def trust_table(points, *, model: str = "slowflow", impact_model: str = "paper") -> str:
    """One line per point: agree / confirmed (% of stable slow-flow states) and the median and
    largest difference to the nearest orbit; a first line names the slow flow compared."""
    lines = [
        f"{_MODEL_NAMES[model]} against the 2pi-orbits of (9)",
        f"{'eps':>5s} {'beta':>4s} {'n':>3s}  {'agree %':>7s} {'confirmed %':>11s} "
        f"{'median diff':>11s} {'max diff':>8s}  warned  status",
    ]
    for p in points:
        lines.append(
            f"{p.eps:5.3g} {p.beta:4.2g} {p.n:3d}  {_percent(p.agree):>7s} "
            f"{_percent(p.confirmed):>11s} {p.median_difference:11.3%} {p.max_difference:8.1%}  "
            f"{'yes' if p.warned else 'no':>6s}  {p.status[:60]}"
        )
    measured = [p for p in points if p.impact_status]
    tag = _IMPACT_TAGS[impact_model]
    if measured:
        lines += [
            "",
            f"the two errors apart, over the stable states with a stable orbit of both {tag} and (9) "
            "nearby" + (" ((C): the corrected impact model)" if impact_model == "corrected" else ""),
            f"{'eps':>5s} {'beta':>4s} {'n':>3s}  {'states':>6s}  {f'(46) vs {tag}: median':>19s} "
            f"{'max':>6s}  {f'{tag} vs (9): median':>18s} {'max':>6s}  status",
        ]
        for p in measured:
            lines.append(
                f"{p.eps:5.3g} {p.beta:4.2g} {p.n:3d}  {p.impact_measured:6d}  {p.asymptotic_median:19.2%} "
                f"{p.asymptotic_max:6.1%}  {p.wall_median:18.2%} {p.wall_max:6.1%}  {p.impact_status[:60]}"
            )
    return "\n".join(lines)


def plot_trust_map(
    points, path, *, title: str = "", model: str = "slowflow", impact_model: str = "paper"
) -> Path:
    """One column of panels per n; eps across, beta up. Top row: fraction of the slow flow's stable
    states within 5 % of some 2pi-orbit of (9); bottom row: of a *stable* orbit. Each cell is
    annotated with that percentage and the median difference; cells where AsymptoticsWarning
    fires are hatched."""
    from matplotlib.patches import Rectangle

    from slosh_bif.report.plotting import pyplot, save_figure

    ns = sorted({p.n for p in points})
    eps = sorted({p.eps for p in points})
    betas = sorted({p.beta for p in points})
    fig, axes = pyplot().subplots(
        2,
        len(ns),
        figsize=(3.2 * len(ns) + 1.2, 6.4),
        squeeze=False,
        sharex=True,
        sharey=True,
        layout="constrained",
    )
    image = None
    for row, (key, label) in enumerate(
        (("agree", "within 5 % of a 2pi-orbit"), ("confirmed", "within 5 % of a stable 2pi-orbit"))
    ):
        for col, n in enumerate(ns):
            ax = axes[row, col]
            grid = np.full((len(betas), len(eps)), np.nan)
            for p in points:
                if p.n == n:
                    i, j = betas.index(p.beta), eps.index(p.eps)
                    grid[i, j] = getattr(p, key)
                    text = (
                        "n/a"
                        if not np.isfinite(grid[i, j])
                        else f"{100 * grid[i, j]:.0f}%\n{p.median_difference:.1%}"
                    )
                    if row == 1 and p.impact_measured:  # the median difference split in two
                        tag = _IMPACT_TAGS[impact_model]
                        text += f"\n(46)-{tag} {p.asymptotic_median:.1%}\n{tag}-(9) {p.wall_median:.1%}"
                    if p.warned:  # hatched at the cell's edge, clear of the numbers
                        ax.add_patch(
                            Rectangle(
                                (j - 0.5, i - 0.5),
                                1,
                                1,
                                fill=False,
                                hatch="//",
                                edgecolor="0.55",
                                lw=0,
                                zorder=2,
                            )
                        )
                    ax.text(
                        j,
                        i,
                        text,
                        ha="center",
                        va="center",
                        fontsize=9,
                        fontweight="bold",
                        zorder=3,
                        bbox=dict(boxstyle="round,pad=0.25", facecolor="white", alpha=0.85, edgecolor="none"),
                    )
            image = ax.imshow(grid, origin="lower", cmap="RdYlGn", vmin=0, vmax=1, aspect="auto")
            ax.set_xticks(range(len(eps)), [f"{e:g}" for e in eps])
            ax.set_yticks(range(len(betas)), [f"{b:g}" for b in betas])
            if row == 0:
                ax.set_title(f"n = {n}")
            if row == 1:
                ax.set_xlabel(r"$\varepsilon$")
            if col == 0:
                ax.set_ylabel(r"$\beta$" + f"\n{label}", fontsize=8)
    fig.colorbar(image, ax=axes, shrink=0.8, label="fraction of stable slow-flow states")
    name = _MODEL_NAMES[model][0].upper() + _MODEL_NAMES[model][1:]
    split = any(p.impact_measured for p in points)
    lines = [
        f"{name} against periodic orbits of (9): % of stable states within 5 %, median difference; "
        "hatched: AsymptoticsWarning"
    ]
    if split:
        lines.append(
            "bottom row: the median split into the expansion's error, (46) against (8), and (8)'s own, "
            "(8) against (9)"
            if impact_model == "paper"
            else "bottom row: the median split into (46) against the corrected impact model (C) and "
            "the contact's duration, (C) against (9)"
        )
    # about 13 characters of the 9-point title per inch of the figure's width
    wrapped = "\n".join(textwrap.fill(line, int(13 * (3.2 * len(ns) + 1.2))) for line in lines)
    fig.suptitle(title or wrapped, fontsize=9)
    return save_figure(fig, path)


def trust_store(path, settings: dict, *, resume: bool):
    """(done, keep) for :func:`~slosh_bif.studies.trust.trust_map`: the points stored in ``path``
    (``trust_map.json``) by an earlier run with the same ``settings`` (resume; else none), and a
    callback that rewrites the file, atomically, as each point finishes. A one-line ValueError
    when resuming from a missing or different store."""
    path = Path(path)
    done = {}
    if resume:
        stored = read_store(path, settings)
        try:
            done = {
                int(i): TrustPoint(**row)
                for i, row in stored["points"].items()
                if not row["status"].startswith("not computed")
            }
        except DAMAGE as err:
            raise damaged(path, err) from None

    def keep(i, point):
        done[i] = point
        write_text_atomically(
            path,
            json.dumps(
                {"settings": settings, "points": {str(k): v.as_row() for k, v in sorted(done.items())}}
            )
            + "\n",
        )

    return dict(done), keep
