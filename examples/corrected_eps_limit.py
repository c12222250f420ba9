"""Which error is left in the slow flows: the impact law, or the first-order expansion in eps?

The slow flows (46) and the corrected one do not contain eps (it only scales time): they are the
eps -> 0 limit of the 2pi-orbits of (9). This script traces the orbits of (9) at three values of
eps (the family of a slow-flow start with its branch switching, and the families the models' stable
states lead to, as ``slosh-bif trust`` finds them), extrapolates their first harmonic A1 to eps = 0
(Richardson, from
the two smallest eps: A1(0) = 2 A1(eps1) - A1(2 eps1), the O(eps) term of the expansion removed),
and measures both slow flows against that limit and against the orbits at the largest eps. A model
that is right up to O(eps) matches the limit; the O(eps) term that neither contains is then the
gap between the limit and the orbits at finite eps (it grows with eps sigma: the coefficients
(1 - eps sigma) / (1 + eps beta^2) of (7) that (8) expands to first order).

Usage: python examples/corrected_eps_limit.py [OUT_DIR] [--preset fig10] [--n N] [--beta B]   (1-5 min)
Writes OUT_DIR/corrected_eps_limit.png and .csv (default OUT_DIR: results/corrected_eps_limit).
"""

import argparse
import csv
import warnings
from pathlib import Path

import numpy as np

from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.starts import slow_flow_start
from slosh_bif.report.plotting import pyplot, save_figure
from slosh_bif.slowflow.flow import AsymptoticsWarning
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies.compare import orbits_at, states_at
from slosh_bif.studies.isolas import missed_families

EPS = (0.01, 0.02, 0.05)  # Richardson from the first two; the third is the paper's grid value
SIGMA_MIN, SIGMA_MAX, GRID = -6.0, 8.0, 57


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="results/corrected_eps_limit")
    parser.add_argument("--preset", default="fig10", help="the set's other parameters (default fig10)")
    parser.add_argument("--n", type=int, default=20)
    parser.add_argument("--beta", type=float, default=0.5)
    args = parser.parse_args(argv)
    base = get_preset(args.preset).params.replace(n=args.n, beta=args.beta)
    sigmas = np.linspace(SIGMA_MIN, SIGMA_MAX, GRID)
    warnings.simplefilter("ignore", AsymptoticsWarning)
    models = {
        name: frequency_response(
            base.replace(eps=EPS[0]), sigma_min=SIGMA_MIN, sigma_max=SIGMA_MAX, model=name
        )
        for name in ("slowflow", "corrected")
    }
    families = {}
    for eps in EPS:
        params = base.replace(eps=eps)
        print(f"orbits of (9) at eps = {eps} (n = {args.n}, beta = {args.beta})", flush=True)
        start = slow_flow_start(params, SIGMA_MIN, SIGMA_MAX, segments=4)
        family = trace_orbits(start.params, start.y0, interval=ParameterRange(lo=SIGMA_MIN, hi=SIGMA_MAX))
        for (
            name,
            fr,
        ) in (
            models.items()
        ):  # the families near the models' states that the first start missed (as `trust` does)
            family.branches.extend(missed_families(params, fr, family, sigmas, model=name))
        families[eps] = family.branches
    rows = []
    for sigma in sigmas:
        for name, fr in models.items():
            for A in (A for A, stable in states_at(fr, sigma) if stable):
                near = {}
                for eps, branches in families.items():
                    orbits = orbits_at(branches, sigma)
                    near[eps] = min((o[0] for o in orbits), key=lambda a: abs(a - A)) if orbits else np.nan
                # nearest orbits more than 10 % apart lie on different branches: no limit from them
                limit = (
                    2 * near[EPS[0]] - near[EPS[1]]
                    if abs(near[EPS[0]] - near[EPS[1]]) < 0.1 * near[EPS[0]]
                    else np.nan
                )
                # the straight line through the first two, at the third eps: how linear in eps A1 is
                line = near[EPS[0]] + (near[EPS[1]] - near[EPS[0]]) * (EPS[2] - EPS[0]) / (EPS[1] - EPS[0])
                rows.append(
                    dict(
                        sigma=sigma,
                        model=name,
                        A=A,
                        **{f"A1_eps{e:g}": near[e] for e in EPS},
                        A1_limit=limit,
                        linearity_defect=abs(line - near[EPS[2]]) / abs(near[EPS[2]] - limit)
                        if np.isfinite(limit)
                        else np.nan,
                        difference_limit=abs(A - limit) / limit,
                        difference_largest_eps=abs(A - near[EPS[-1]]) / near[EPS[-1]],
                    )
                )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "corrected_eps_limit.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plt = pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(8, 8), sharex=True)
    for k, eps in enumerate(EPS):
        for j, b in enumerate(families[eps]):
            axes[0].plot(
                b.branch.p,
                b.measures["A1"],
                color=f"C{k + 2}",
                lw=1,
                label=f"(9), eps = {eps:g}" if j == 0 else None,
            )
    labels = {"slowflow": "(46)", "corrected": "corrected"}
    for k, name in enumerate(models):
        sub = [r for r in rows if r["model"] == name]
        axes[0].plot(
            [r["sigma"] for r in sub],
            [r["A"] for r in sub],
            "o" if k == 0 else "s",
            ms=3,
            color=f"C{k}",
            label=labels[name],
        )
        axes[1].plot(
            [r["sigma"] for r in sub],
            [100 * r["difference_limit"] for r in sub],
            "o-" if k == 0 else "s-",
            ms=3,
            color=f"C{k}",
            label=f"{labels[name]} against the eps -> 0 limit of (9)",
        )
        axes[1].plot(
            [r["sigma"] for r in sub],
            [100 * r["difference_largest_eps"] for r in sub],
            ":",
            color=f"C{k}",
            label=f"{labels[name]} against (9) at eps = {EPS[-1]:g}",
        )
        print(
            f"{labels[name]:>9}: median difference against the eps -> 0 limit "
            f"{100 * np.nanmedian([r['difference_limit'] for r in sub]):.1f} %, "
            f"against eps = {EPS[-1]:g} "
            f"{100 * np.nanmedian([r['difference_largest_eps'] for r in sub]):.1f} % ({len(sub)} "
            "stable states; "
            f"{sum(np.isfinite(r['difference_limit']) for r in sub)} with a limit; the straight "
            f"line in eps misses (9) at eps = {EPS[-1]:g} by "
            f"{100 * np.nanmedian([r['linearity_defect'] for r in sub]):.0f} % of its O(eps) shift, median)"
        )
    limit_rows = [r for r in rows if r["model"] == "corrected"]
    axes[0].plot(
        [r["sigma"] for r in limit_rows],
        [r["A1_limit"] for r in limit_rows],
        "k--",
        lw=1,
        label="(9), eps -> 0 (Richardson)",
    )
    axes[0].set_yscale("log")
    axes[0].set_ylabel("A1 (first harmonic of X)")
    axes[0].legend(fontsize=7)
    axes[0].set_title(
        f"{args.preset} set, n = {args.n}, beta = {args.beta:g}: the slow flows against (9) and "
        "its eps -> 0 limit"
    )
    axes[1].set_ylabel("relative difference (%)")
    axes[1].set_xlabel("sigma")
    axes[1].set_ylim(0, 30)
    axes[1].grid(alpha=0.3)
    axes[1].legend(fontsize=7)
    print("wrote", save_figure(fig, out / "corrected_eps_limit.png"))


if __name__ == "__main__":
    main()
