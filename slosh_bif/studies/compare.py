"""The slow flow (46) against the periodic orbits of (9), and optionally of (8):
``compare.csv``, ``compare.txt``, ``compare.png``.

``compare.csv``: on a sigma grid, the slow-flow amplitude A of eq. (46) on each stable/unstable
state against the first-harmonic amplitude A1 of the nearest orbit of the shooting branches,
with the relative difference, and the same against the nearest stable orbit
(``A1_stable_orbit``, ``stable_orbit_branch``, ``relative_difference_stable_orbit``). With the
orbits of the vibro-impact model (8) (rows of :func:`~slosh_bif.orbits.impact.output.impact_rows`)
beside them: ``A1_impact``, the stable orbit of (8) nearest the slow-flow state,
``relative_difference_impact`` = |A1_impact - A| / A, the expansion's own error (the slow flow is
derived from (8), with the same rigid wall and restitution law (21)), and ``wall_difference`` =
|A1_impact - A1_stable_orbit| / A1_stable_orbit, the error of the rigid-wall idealisation against
(9) at its n: the two errors that every slow-flow-against-(9) number mixes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.orbits.orbit_branch import OrbitFamily
from slosh_bif.report.tables import write_rows
from slosh_bif.slowflow.steady_states import FrequencyResponse

__all__ = [
    "COMPARE_COLUMNS",
    "IMPACT_COLUMNS",
    "compare_rows",
    "impact_branch_rows",
    "impact_errors",
    "impact_orbits_at",
    "stable_at",
    "write_compare_csv",
    "compare_table",
    "plot_compare",
]

COMPARE_COLUMNS = (
    "sigma",
    "A_slow_flow",
    "slow_flow_stable",
    "A1_shooting",
    "shooting_stable",
    "shooting_branch",
    "relative_difference",
    "A1_stable_orbit",
    "stable_orbit_branch",
    "relative_difference_stable_orbit",
)
IMPACT_COLUMNS = ("A1_impact", "relative_difference_impact", "wall_difference")
IMPACT_NAMES = {"paper": "impact model (8)", "corrected": "corrected impact model"}
IMPACT_LABELS = {  # what the two impact columns measure, for (8) and for the corrected impact model
    "paper": (
        ("asymptotic", "the expansion's error, slow flow against (8)"),
        ("wall", "(8)'s own error, (8) against (9) (its first-order coefficients and its wall)"),
    ),
    "corrected": (
        ("asymptotic", "slow flow against the corrected impact model"),
        ("wall", "the contact's duration, the corrected impact model against (9)"),
    ),
}


def compare_rows(family: OrbitFamily, fr: FrequencyResponse, sigmas, impact=None):
    """For each sigma and each slow-flow state there: the orbit (on any traced 2pi branch) whose
    A1 is nearest, with the relative difference |A1 - A| / A, and the nearest *stable* orbit with
    its difference (stable to stable: what a simulation of (9) would settle on, if periodic).
    ``impact``: rows of orbits of (8) (``impact_rows``), for the columns of :data:`IMPACT_COLUMNS`."""
    nan = float("nan")
    nothing = dict(
        A1_shooting=nan,
        shooting_stable="",
        shooting_branch="",
        relative_difference=nan,
        A1_stable_orbit=nan,
        stable_orbit_branch="",
        relative_difference_stable_orbit=nan,
    )
    if impact is not None:
        nothing.update(A1_impact=nan, relative_difference_impact=nan, wall_difference=nan)
    for sigma in sigmas:
        slow = states_at(fr, sigma)
        orbits = orbits_at(family.branches, sigma)
        stable_orbits = [o for o in orbits if o[1]]
        stable_impact = [o for o in impact_orbits_at(impact, sigma) if o[1]] if impact is not None else []
        for A, stable in slow:
            row = dict(sigma=float(sigma), A_slow_flow=A, slow_flow_stable=int(stable), **nothing)
            if orbits:
                A1, ostable, name = min(orbits, key=lambda o: abs(o[0] - A))
                row.update(
                    A1_shooting=A1,
                    shooting_stable=int(ostable),
                    shooting_branch=name,
                    relative_difference=abs(A1 - A) / A,
                )
            if stable_orbits:
                A1, _, name = min(stable_orbits, key=lambda o: abs(o[0] - A))
                row.update(
                    A1_stable_orbit=A1,
                    stable_orbit_branch=name,
                    relative_difference_stable_orbit=abs(A1 - A) / A,
                )
            if stable_impact:
                A8 = min(stable_impact, key=lambda o: abs(o[0] - A))[0]
                row.update(
                    A1_impact=A8,
                    relative_difference_impact=abs(A8 - A) / A,
                    wall_difference=abs(A8 - row["A1_stable_orbit"]) / row["A1_stable_orbit"],
                )
            yield row


def impact_branch_rows(
    params, state0, sigma_min: float, sigma_max: float, *, settle: int, variant: str = "paper"
) -> list:
    """Rows (:func:`~slosh_bif.orbits.impact.output.impact_rows`) of the branch of orbits of (8)
    (``variant="corrected"``: of the corrected impact model) through the orbit a ``settle``-period
    simulation from ``state0`` settles on at the set's sigma (else from the slow flow's steady
    states in the range, as ``shoot --model impact``), over
    [sigma_min, sigma_max], at steps of at most 0.05 so that A1 read between points is within
    about 1e-4 of the orbit's (0.3 % at shoot's 0.3); the ``criticality`` column says how each
    LP, PD, NS and BP is crossed."""
    from slosh_bif.continuation import ContinuationOptions
    from slosh_bif.orbits.criticality import Verdict, impact_criticality, phrases
    from slosh_bif.orbits.impact.branches import trace_impact_orbits
    from slosh_bif.orbits.impact.output import impact_rows
    from slosh_bif.orbits.impact.starts import impact_start

    start = impact_start(params, state0, periods=settle, p_range=(sigma_min, sigma_max), variant=variant)
    result = trace_impact_orbits(
        start.params,
        start.x,
        p_min=sigma_min,
        p_max=sigma_max,
        options=ContinuationOptions(step=0.02, step_max=0.05, tol=1e-10),
        variant=variant,
    )
    # verdicts and the reasons a point was not judged; the branch is traced on the whole-period map,
    # where a symmetric orbit's pitchfork is no meeting with a parent (its verdict needs the half map)
    judged = phrases(
        impact_criticality(result, params),
        keep=lambda v: isinstance(v, Verdict) or v.startswith("not computed"),
    )
    return list(impact_rows(result, params, criticality=judged))


def impact_errors(rows) -> dict:
    """The median and largest of the expansion's error (``relative_difference_impact``: (46)
    against (8)) and of the wall's (``wall_difference``: (8) against (9)) over the rows of stable
    slow-flow states where both were measured, and how many such rows there are."""
    both = [
        (r["relative_difference_impact"], r["wall_difference"])
        for r in rows
        if r["slow_flow_stable"]
        and np.isfinite(r.get("relative_difference_impact", np.nan))
        and np.isfinite(r.get("wall_difference", np.nan))
    ]
    if not both:
        nan = float("nan")
        return dict(measured=0, asymptotic_median=nan, asymptotic_max=nan, wall_median=nan, wall_max=nan)
    a, w = np.array(both).T
    return dict(
        measured=len(both),
        asymptotic_median=float(np.median(a)),
        asymptotic_max=float(a.max()),
        wall_median=float(np.median(w)),
        wall_max=float(w.max()),
    )


def impact_orbits_at(rows, sigma) -> list:
    """(A1, stable, piece) of every orbit of (8) at ``sigma`` in ``rows`` (of ``impact_rows``):
    linear in A1 between neighbouring rows of one piece; the stability of the nearer row, or of the
    farther where the nearer is a special point (its multiplier on the circle, its flag rounding).
    Pieces that overlap (the same orbits across a moved section) count once."""
    found = []
    for piece in sorted({(r.get("branch", ""), r["piece"]) for r in rows}):
        part = sorted(
            (r for r in rows if (r.get("branch", ""), r["piece"]) == piece), key=lambda r: r["sigma"]
        )
        for a, b in zip(part, part[1:]):
            if a["sigma"] <= sigma <= b["sigma"] and a["sigma"] < b["sigma"]:
                w = (sigma - a["sigma"]) / (b["sigma"] - a["sigma"])
                near, far = (a, b) if w <= 0.5 else (b, a)
                stable = far["stable"] if near["special"] and near["special"] != "END" else near["stable"]
                found.append((a["A1"] + w * (b["A1"] - a["A1"]), bool(stable), piece))
    kept = []
    for f in sorted(found):
        same = [g for g in kept if g[1] == f[1]]
        if not same or f[0] - same[-1][0] > 1e-3 * f[0]:
            kept.append(f)
    return kept


def states_at(fr: FrequencyResponse, sigma) -> list:
    """(A, stable) of every steady state of a slow flow's frequency response at ``sigma`` (A linear
    between a branch's points, the stability of the nearer point)."""
    return [
        (float(np.interp(sigma, b.p[s], b.x[s, 0])), bool(b.stable[s][i]))
        for b in fr.branches
        for s, i in _crossings(b.p, sigma)
    ]


def orbits_at(branches, sigma) -> list:
    """(A1, stable, branch name) of every 2pi-orbit of the OrbitBranches ``branches`` at ``sigma``
    (linear in A1 between a branch's points)."""
    two_pi = [ob for ob in branches if ob.problem.period_multiple == 1]
    return [
        (
            float(ob.measures["A1"][s][0] + (ob.measures["A1"][s][1] - ob.measures["A1"][s][0]) * w),
            stable_at(ob.branch, s, sigma),
            ob.name,
        )
        for ob in two_pi
        for s, w in _segments(ob.branch.p, sigma)
    ]


def _segments(p, value):
    """(slice of two indices, weight) for each branch segment that crosses p = value."""
    for i in range(len(p) - 1):
        lo, hi = p[i], p[i + 1]
        if (lo - value) * (hi - value) <= 0 and lo != hi:
            yield slice(i, i + 2), (value - lo) / (hi - lo)


_STABILITY_CHANGES = ("LP", "BP", "PD", "NS")


def stable_at(branch, s, sigma) -> bool:
    """Whether the branch's orbit at ``sigma`` in the segment ``s`` is stable, decided by the end
    on sigma's side of the located special point (LP, BP, PD or NS) in the segment, if one is:
    not by where the continuation happened to put its points, nor by the special point's own
    flag, whose critical multiplier is 1 to rounding (both made a stable state's verdict depend on
    the last bits of libm's cos and pow, which differ between CPUs: 4 of 48 trust rows). With no
    special point the ends decide (unstable where they disagree, as before). A special point of
    another part of the branch at a parameter value inside the segment's does not count."""
    i = s.start
    lo, hi = branch.p[i], branch.p[i + 1]
    ends = ((lo, bool(branch.stable[i])), (hi, bool(branch.stable[i + 1])))
    tol = 1e-12 * (1 + abs(lo) + abs(hi))
    inside = [  # of this segment: a branch that turns back has others at the same parameter values
        sp.p
        for sp in branch.special
        if sp.located
        and sp.kind in _STABILITY_CHANGES
        and i <= sp.index <= i + 1
        and min(lo, hi) - tol <= sp.p <= max(lo, hi) + tol
    ]
    if len(inside) == 1:
        side = [
            flag
            for p, flag in ends
            if abs(p - inside[0]) > tol and (p - inside[0]) * (sigma - inside[0]) >= 0
        ]
        if side:
            return side[0]
    return ends[0][1] and ends[1][1]


def _crossings(p, value):
    for s, w in _segments(p, value):
        yield s, 0 if w < 0.5 else 1


def write_compare_csv(rows, path) -> Path:
    with_impact = bool(rows) and "A1_impact" in rows[0]
    return write_rows(rows, COMPARE_COLUMNS + (IMPACT_COLUMNS if with_impact else ()), path)


def compare_table(rows, *, agree: float = 0.05, impact_model: str = "paper") -> str:
    """Sigma intervals where the slow flow's stable states agree with the nearest orbit to
    within ``agree`` (relative), and where not, with the largest differences."""
    rows = [r for r in rows if r["slow_flow_stable"]]
    if not rows:
        return "no stable slow-flow state in the range"
    lines = [f"{'sigma range':>24s}  {'verdict':28s} {'max rel. diff':>13s}  {'orbit stable?':>13s}"]
    run = [rows[0]]

    def verdict(r):
        d = r["relative_difference"]
        return "no orbit" if not np.isfinite(d) else ("agree" if d <= agree else "differ")

    def flush(run):
        d = [r["relative_difference"] for r in run if np.isfinite(r["relative_difference"])]
        stable = {r["shooting_stable"] for r in run} - {""}
        st = "yes" if stable == {1} else ("no" if stable == {0} else ("mixed" if stable else "-"))
        text = f"{verdict(run[0])} (within {agree:.0%})" if verdict(run[0]) == "agree" else verdict(run[0])
        lines.append(
            f"[{run[0]['sigma']:9.4f}, {run[-1]['sigma']:9.4f}]  {text:28s} "
            f"{max(d) if d else float('nan'):13.3%}  {st:>13s}"
        )

    for r in rows[1:]:
        if verdict(r) == verdict(run[-1]):
            run.append(r)
        else:
            flush(run)
            run = [r]
    flush(run)
    confirmed = sum(r["relative_difference_stable_orbit"] <= agree for r in rows)
    lines.append(
        f"stable slow-flow states with a stable 2pi-orbit of (9) within {agree:.0%}: {confirmed} "
        f"of {len(rows)}"
    )
    if "A1_impact" in rows[0]:
        errors = impact_errors(rows)
        for key, what in IMPACT_LABELS[impact_model]:
            lines.append(
                f"{what}: median {errors[key + '_median']:.2%}, largest {errors[key + '_max']:.2%} "
                f"over {errors['measured']} states"
                if errors["measured"]
                else f"{what}: no state with both"
            )
    return "\n".join(lines)


def plot_compare(
    family: OrbitFamily, fr: FrequencyResponse, rows, path, impact=None, impact_model: str = "paper"
) -> Path:
    from slosh_bif.orbits.impact.problem import VARIANT_NAMES
    from slosh_bif.report.plotting import pyplot, save_figure

    fig, (ax, axd) = pyplot().subplots(
        2, 1, figsize=(9, 7.5), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]}
    )
    name = "slow flow (46)" if fr.model == "slowflow" else "corrected slow flow"
    for k, b in enumerate(fr.branches):
        for st, ls in ((True, "-"), (False, "--")):
            y = np.where(b.stable == st, b.x[:, 0], np.nan)
            ax.plot(
                b.p,
                y,
                ls,
                color="k",
                lw=2,
                label=(f"{name}, stable" if st else f"{name}, unstable") if k == 0 else None,
            )
    for k, ob in enumerate(ob for ob in family.branches if ob.problem.period_multiple == 1):
        b = ob.branch
        for st, marker in ((True, "o"), (False, ".")):
            mask = b.stable == st
            ax.plot(
                b.p[mask],
                ob.measures["A1"][mask],
                marker,
                ms=3 if st else 2,
                color=f"C{k}",
                label=f"shooting (9), {ob.name}, {'stable' if st else 'unstable'}",
            )
    if impact:
        s8 = np.array([r["sigma"] for r in impact])
        a8 = np.array([r["A1"] for r in impact])
        st8 = np.array([bool(r["stable"]) for r in impact])
        impact_name = IMPACT_NAMES[impact_model]
        ax.plot(s8[st8], a8[st8], "s", ms=2.5, mfc="none", color="C3", label=f"{impact_name}, stable")
        ax.plot(s8[~st8], a8[~st8], "x", ms=2.5, color="C3", alpha=0.5, label=f"{impact_name}, unstable")
    ax.set_ylabel("amplitude of X (A; A1 for orbits)")
    P = family.params
    ax.set_title(
        f"{name[0].upper() + name[1:]} against periodic orbits of "
        f"(9){' and ' + VARIANT_NAMES[impact_model] if impact else ''}: eps = {P.eps:g}, "
        f"beta = {P.beta:g}, Abar = {P.Abar:g}, n = {P.n}"
    )
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    s = np.array([r["sigma"] for r in rows], dtype=float)
    d = np.array([r["relative_difference"] for r in rows], dtype=float)
    st = np.array([bool(r["slow_flow_stable"]) for r in rows], dtype=bool)
    axd.semilogy(s[st], d[st], "k.", ms=3, label="stable slow-flow states")
    axd.semilogy(s[~st], d[~st], ".", color="0.6", ms=3, label="unstable slow-flow states")
    if impact:
        for key, style, label in (
            ("relative_difference_impact", "s", IMPACT_LABELS[impact_model][0][1]),
            ("wall_difference", "^", IMPACT_LABELS[impact_model][1][1]),
        ):
            axd.semilogy(
                s, np.array([r[key] for r in rows], dtype=float), style, ms=3, mfc="none", label=label
            )
    axd.set_ylabel("|A1 - A| / A")
    axd.set_xlabel(r"$\sigma$")
    axd.legend(fontsize=7)
    axd.grid(alpha=0.3)
    return save_figure(fig, path)
