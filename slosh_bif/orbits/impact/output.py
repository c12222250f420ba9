"""Writing a branch of periodic orbits of the vibro-impact model (8) as CSV and PNG.

``branch.csv``: one row per point, pieces one after another
(:mod:`slosh_bif.orbits.impact.branches`), columns ``sigma, Abar, A1, max_abs_X, impacts,
min_impact_speed, stable, max_abs_multiplier, special, branch, piece, phase``: A1 is the
first-harmonic amplitude of X at the forcing frequency, as for (9); ``impacts`` the impacts per
period of the orbit on the piece (twice those of the half period on a symmetric branch, traced on
the half-period map; over 4 pi on a period-2 branch), ``phase`` its section; ``special`` the
special point at that row (PD, NS, LP, BP, GR at a grazing end, END), ``criticality`` how an LP,
PD, NS or BP there is crossed (soft, hard, a jump; :mod:`slosh_bif.orbits.criticality`); ``branch`` its name
(``symmetric``, ``asymmetric``, ``asymmetric-2``, ..., ``period-2`` (born at a period doubling),
or ``primary`` when the start orbit is not symmetric).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.orbits.impact.branches import ImpactBranch
from slosh_bif.orbits.impact.problem import GRAZING, ImpactOrbitProblem
from slosh_bif.report.tables import write_rows

__all__ = [
    "IMPACT_COLUMNS",
    "first_harmonic",
    "orbit_measures",
    "impact_rows",
    "write_impact_csv",
    "plot_impact_branch",
]

IMPACT_COLUMNS = (
    "sigma",
    "Abar",
    "A1",
    "max_abs_X",
    "impacts",
    "min_impact_speed",
    "stable",
    "max_abs_multiplier",
    "special",
    "criticality",
    "branch",
    "piece",
    "phase",
)
MEASURE_STEP = 0.01  # sample step of an orbit for its measures: A1 to about 1e-5


def first_harmonic(t, X) -> float:
    """A1 of X sampled at t over a whole period of the orbit (2 pi times its multiple): 2/T times
    the trapezoid rule's integral of X exp(-i t)."""
    f = X * np.exp(-1j * t)
    return float(abs(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t)) / (0.5 * (t[-1] - t[0]))))


def orbit_measures(problem: ImpactOrbitProblem, x, p) -> dict:
    """A1, max |X|, max |w| (1 on an orbit with impacts) and the slowest impact speed of the orbit
    of (8) through x on the problem's section."""
    t, y, impacts = problem.orbit(x, p, step=MEASURE_STEP)
    if problem.symmetric:  # over half its period: the other half is -y
        t, y = np.concatenate([t, t[1:] + problem.period]), np.concatenate([y, -y[:, 1:]], axis=1)
    return {
        "A1": first_harmonic(t, y[0]),
        "max_abs_X": float(np.abs(y[0]).max()),
        "max_abs_w": float(np.abs(y[2]).max()),
        "min_impact_speed": float(np.abs(impacts[:, 2]).min()) if len(impacts) else float("nan"),
    }


def _labels(branch):
    labels = [""] * len(branch)
    for s in branch.special:
        kind = "GR" if s.kind == "END" and s.edge == GRAZING else s.kind
        labels[s.index] = f"{labels[s.index]} {kind}".strip()
    return labels


def impact_rows(
    result: ImpactBranch, params, symmetric: bool = False, name: str = "primary", criticality=None
):
    """One row per point of every piece of ``result`` (traced on the half-period map when
    ``symmetric``), named ``name`` in the ``branch`` column; ``criticality``, per piece, ``{index
    of a special point: its phrase}`` for the ``criticality`` column."""
    for k, piece in enumerate(result.pieces):
        b = piece.branch
        labels = _labels(b)
        phrases = [""] * len(b)
        for j, phrase in (criticality[k] if criticality else {}).items():
            i = b.special[j].index
            phrases[i] = f"{phrases[i]}; {phrase}" if phrases[i] else phrase
        problem = ImpactOrbitProblem(
            params,
            b.param,
            symmetric=symmetric,
            phase=piece.phase,
            period_multiple=piece.period_multiple,
            variant=result.variant,
        )
        for i in range(len(b)):
            at = params.replace(**{b.param: float(b.p[i])})
            m = orbit_measures(problem, b.x[i], b.p[i])
            yield {
                "sigma": at.sigma,
                "Abar": at.Abar,
                **m,
                "impacts": piece.impacts * (2 if symmetric else 1),
                "stable": int(b.stable[i]),
                "max_abs_multiplier": float(np.abs(b.eigenvalues[i]).max()),
                "special": labels[i],
                "criticality": phrases[i],
                "branch": name,
                "piece": k,
                "phase": piece.phase,
            }


def write_impact_csv(rows, path) -> Path:
    return write_rows(rows, IMPACT_COLUMNS, path)


def plot_impact_branch(rows, params, path, *, title=None) -> Path:
    """A1 against the parameter (stable solid, unstable dashed, special points marked) and the
    impacts per period below."""
    from slosh_bif.report.plotting import (
        SPECIAL_MARKERS,
        branch_legend,
        mark_special,
        pyplot,
        save_figure,
        stability_runs,
    )

    rows = list(rows)
    param = "sigma" if len({r["sigma"] for r in rows}) > 1 else "Abar"
    fig, (ax, axi) = pyplot().subplots(
        2, 1, figsize=(9, 7.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    points = []
    names = list(dict.fromkeys(r["branch"] for r in rows))
    for name, k in sorted(
        {(r["branch"], r["piece"]) for r in rows}, key=lambda nk: (names.index(nk[0]), nk[1])
    ):
        part = [r for r in rows if (r["branch"], r["piece"]) == (name, k)]
        color = f"C{names.index(name)}"
        p = np.array([r[param] for r in part])
        a1 = np.array([r["A1"] for r in part])
        stable = np.array([r["stable"] for r in part], dtype=bool)
        for a, b in stability_runs(stable):  # one line per run (one per segment cost seconds)
            ax.plot(p[a : b + 1], a1[a : b + 1], "-" if stable[a] else "--", color=color, lw=1.4)
        axi.plot(p, [r["impacts"] for r in part], color=color, lw=1.2)
        points += [
            (r[param], r["A1"], kind)
            for r in part
            for kind in r["special"].split()
            if kind in SPECIAL_MARKERS and kind != "END"
        ]
    mark_special(ax, points, ms=7)
    for j, name in enumerate(names if len(names) > 1 else ()):
        ax.plot([], [], "-", color=f"C{j}", lw=3, label=name)
    stable = [bool(r["stable"]) for r in rows]
    branch_legend(ax, stable=any(stable), unstable=not all(stable), kinds={k for _, _, k in points})
    ax.set_ylabel("A1: first-harmonic amplitude of X")
    axi.set_ylabel("impacts / period")
    axi.set_xlabel(r"$\sigma$" if param == "sigma" else r"$\bar A$")
    ax.set_title(
        title
        or f"Periodic orbits of the impact model (8): eps = {params.eps:g}, beta = {params.beta:g}, "
        f"gamma = {params.gamma:g}, Abar = {params.Abar:g}, n = {params.n}"
    )
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    axi.grid(alpha=0.3)
    return save_figure(fig, path)
