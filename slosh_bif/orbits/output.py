"""Writing families of periodic orbits of (9) as CSV and PNG.

``branch.csv``: one row per point in branch order, branches one after another, columns
``sigma, Abar, A1, max_abs_X, max_abs_w, stable, max_abs_multiplier, liouville_error,
symmetry_defect, special, criticality, branch, status, flag``: ``criticality`` says at each LP,
PD, NS and BP point whether the loss of stability there is soft or hard, with its normal-form
coefficient (:mod:`slosh_bif.orbits.criticality`); ``status`` is the branch's (``ok``, or why it
was cut short: ``step below minimum``, ``step limit``, ``time limit``), ``flag`` is ``liouville``
where the point's Liouville check fails beyond :data:`~slosh_bif.orbits.families.LIOUVILLE_TOL`
(its multipliers, hence its stability, are not reliable), else empty; ``branch`` is the branch's
unique name.

``families.csv``: one row per branch, columns ``family, kind, sigma_min, sigma_max, closed,
found_from, points, status``: ``family`` the unique name (as in ``branch.csv``), ``kind``
symmetric, asymmetric, period-2, ...; the sigma range it covers; ``closed`` 1 when it closed on
itself (an isola or a loop) or ended where it meets its parent again (the rest of its loop is
the image of what it traced); ``found_from`` the start that found it or the point it was switched
on at; ``status`` as in ``branch.csv``.
"""

from __future__ import annotations

from pathlib import Path

from slosh_bif.orbits.criticality import describe
from slosh_bif.orbits.orbit_branch import LIOUVILLE_TOL, OrbitFamily
from slosh_bif.report.tables import write_rows

__all__ = [
    "BRANCH_COLUMNS",
    "FAMILY_COLUMNS",
    "family_rows",
    "write_branch_csv",
    "write_families_csv",
    "plot_family",
]

BRANCH_COLUMNS = (
    "sigma",
    "Abar",
    "A1",
    "max_abs_X",
    "max_abs_w",
    "stable",
    "max_abs_multiplier",
    "liouville_error",
    "symmetry_defect",
    "special",
    "criticality",
    "branch",
    "status",
    "flag",
)

FAMILY_COLUMNS = ("family", "kind", "sigma_min", "sigma_max", "closed", "found_from", "points", "status")


def family_rows(family: OrbitFamily, verdicts=None):
    """The rows of ``branch.csv``; ``verdicts`` per branch (:func:`~.criticality.special_criticality`
    of each, None: not computed) fill the ``criticality`` column at the special points."""
    for j, ob in enumerate(family.branches):
        b, m = ob.branch, ob.measures
        labels = b.special_labels()
        phrases = {}
        for k, v in (verdicts[j] if verdicts is not None else {}).items():
            sp = b.special[k]
            phrases.setdefault(sp.index, []).append(f"{sp.kind} {describe(v)}")
        for i in range(len(b)):
            sigma, Abar = (
                (b.p[i], family.params.Abar) if b.param == "sigma" else (family.params.sigma, b.p[i])
            )
            yield {
                "sigma": float(sigma),
                "Abar": float(Abar),
                **{
                    k: float(m[k][i])
                    for k in (
                        "A1",
                        "max_abs_X",
                        "max_abs_w",
                        "max_abs_multiplier",
                        "liouville_error",
                        "symmetry_defect",
                    )
                },
                "stable": int(b.stable[i]),
                "special": labels[i],
                "criticality": "; ".join(phrases.get(i, [])),
                "branch": ob.name,
                "status": b.status,
                "flag": "liouville" if m["liouville_error"][i] > LIOUVILLE_TOL else "",
            }


def write_branch_csv(family: OrbitFamily, path, verdicts=None) -> Path:
    return write_rows(family_rows(family, verdicts), BRANCH_COLUMNS, path)


def write_families_csv(family: OrbitFamily, path) -> Path:
    def rows():
        for ob in family.branches:
            sigma = ob.branch.p if ob.branch.param == "sigma" else [family.params.sigma]
            yield {
                "family": ob.name,
                "kind": ob.kind,
                "sigma_min": float(min(sigma)),
                "sigma_max": float(max(sigma)),
                "closed": int(ob.closed),
                "found_from": ob.found_from,
                "points": len(ob),
                "status": ob.branch.status,
            }

    return write_rows(rows(), FAMILY_COLUMNS, path)


def plot_family(family: OrbitFamily, path, *, slow_flow=None, title=None) -> Path:
    """A1 against the parameter for every branch (stable solid, unstable dashed, special points
    marked), with the slow-flow curve in grey when given (``slow_flow``: a frequency response of
    (46), anything with ``branches``); the largest multiplier below."""
    from slosh_bif.report.plotting import branch_legend, drawn, plot_branch, pyplot, save_figure

    fig, (ax, axm) = pyplot().subplots(
        2, 1, figsize=(9, 8), sharex=True, gridspec_kw={"height_ratios": [3, 1.2]}
    )
    if slow_flow is not None:
        for k, branch in enumerate(slow_flow.branches):
            ax.plot(
                branch.p,
                branch.x[:, 0],
                color="0.6",
                lw=3,
                alpha=0.6,
                label="slow flow (46)" if k == 0 else None,
            )
    for k, ob in enumerate(family.branches):
        b = ob.branch
        plot_branch(
            ax,
            b,
            ob.measures["A1"],
            color=f"C{k}",
            label=f"{ob.name}" + (f" ({ob.origin})" if ob.origin else ""),
            label_ends=False,
            annotate=len(b.special) <= 12,
        )
        axm.semilogy(b.p, ob.measures["max_abs_multiplier"], color=f"C{k}", lw=1)
    from matplotlib.ticker import LogFormatter

    # plain tick labels and Unicode symbols: mathtext's parser costs 0.4 s to build, a tenth of a
    # whole shooting run
    axm.yaxis.set_major_formatter(LogFormatter(labelOnlyBase=True))
    branch_legend(ax, **drawn(ob.branch for ob in family.branches))
    axm.axhline(1, color="k", lw=0.8)
    axm.set_ylabel("max |multiplier|")
    axm.set_xlabel("\u03c3" if family.param == "sigma" else "\u0100")
    ax.set_ylabel("A1: first-harmonic amplitude of X")
    P = family.params
    ax.set_title(
        title
        or f"Periodic orbits of (9) by shooting: eps = {P.eps:g}, beta = {P.beta:g}, gamma = "
        f"{P.gamma:g}, Abar = {P.Abar:g}, n = {P.n}"
    )
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    axm.grid(alpha=0.3)
    # fixed margins, room for tick labels as wide as 1e+15, both y labels at one place: tight_layout
    # measures every text once more, 0.1 s of the figure's 0.25 s, which a whole shoot run waits for
    fig.subplots_adjust(left=0.09, right=0.985, bottom=0.065, top=0.955, hspace=0.1)
    for axis in (ax, axm):
        axis.yaxis.set_label_coords(-0.075, 0.5)
    return save_figure(fig, path, layout=False)
