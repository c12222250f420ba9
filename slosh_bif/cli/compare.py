"""``slosh-bif compare``: the slow flow's frequency response (46) against the shooting branches of
(9) over the same sigma range (and with ``--impact`` the orbits of (8)), and how each response
loses stability."""

from __future__ import annotations

import numpy as np

from slosh_bif.cli.common import (
    add_impact_model_option,
    add_model_option,
    add_params_options,
    add_range_options,
    add_sigma_points_option,
    check_impact_model,
    check_sigma_points,
    params_of,
    progress,
    sigma_range,
    state0_of,
)
from slosh_bif.cli.orbits import add_shooting_options, check_family_options, family_from_args
from slosh_bif.report.files import write_text_atomically

__all__ = ["add_commands"]


def _compare(args) -> int:
    from slosh_bif.cli.terminal import REPORTER
    from slosh_bif.orbits.criticality import family_criticality
    from slosh_bif.slowflow.steady_states import frequency_response
    from slosh_bif.studies.compare import (
        compare_rows,
        compare_table,
        plot_compare,
        write_compare_csv,
    )

    params = params_of(args)
    lo, hi = sigma_range(args)
    check_sigma_points(args)
    check_family_options(args)
    args.out.mkdir(parents=True, exist_ok=True)
    check_impact_model(args)
    if args.impact:
        params.require_positive_stiffness()
        if not lo <= params.sigma <= hi:
            raise ValueError(
                f"--impact starts (8)'s branch at the set's sigma = {params.sigma:g}, which must "
                f"lie in [{lo:g}, {hi:g}]"
            )
    fr = frequency_response(params, sigma_min=lo, sigma_max=hi, model=args.model)
    family = family_from_args(args, params, lo, hi)
    impact = _impact_branch_rows(args, params, lo, hi) if args.impact else None
    rows = list(compare_rows(family, fr, np.linspace(lo, hi, args.sigma_points), impact))
    csv_path, png_path = (
        write_compare_csv(rows, args.out / "compare.csv"),
        plot_compare(family, fr, rows, args.out / "compare.png", impact, impact_model=args.impact_model),
    )
    table = compare_table(rows, impact_model=args.impact_model)
    verdicts = family_criticality(family.branches)
    losses = [_losses(fr, family, verdicts, impact, every=every) for every in (True, REPORTER.verbose)]
    write_text_atomically(args.out / "compare.txt", table + "\n" + losses[0] + "\n")
    print(table + "\n" + losses[1])
    print(f"wrote {csv_path}, {png_path}, {args.out / 'compare.txt'}")
    return 0


def _losses(fr, family, verdicts, impact, *, every: bool) -> str:
    """How each response loses stability: the slow flow's folds (a jump: the steady state of (46)
    ends there), each LP, PD, NS and BP of (9)'s family with its normal form's verdict
    (``verdicts``; past 30 of them one line counts them, unless ``every``) and those of (8)'s
    branch (``impact``, its rows, or None)."""
    from slosh_bif.orbits.criticality import verdict_lines

    folds = sorted(sp.p for b in fr.branches for sp in b.special if sp.kind == "LP")
    lines = ["how stability is lost:"]
    lines += [
        f"  LP at sigma = {p:.6g} of the slow flow: a jump (a fold of the steady states)" for p in folds
    ]
    if not folds:
        lines.append("  the slow flow's steady states have no fold in the range")
    lines += verdict_lines(family, verdicts, every=every, where="compare.txt")
    lines += [
        f"  {r['special']} at sigma = {r['sigma']:.6g} of the impact model: {r['criticality']}"
        for r in impact or ()
        if r.get("criticality")
    ]
    return "\n".join(lines)


def _impact_branch_rows(args, params, lo, hi) -> list:
    from slosh_bif.studies.compare import impact_branch_rows

    progress(f"orbits of (8) from a {args.settle}-period simulation at sigma = {params.sigma:g}")
    rows = impact_branch_rows(
        params, state0_of(args, params), lo, hi, settle=args.settle, variant=args.impact_model
    )
    progress(
        f"orbits of (8): {len(rows)} points over sigma in [{min(r['sigma'] for r in rows):.6g}, "
        f"{max(r['sigma'] for r in rows):.6g}]"
    )
    return rows


def add_commands(sub) -> None:
    """Register ``compare`` on the ``slosh-bif`` subparsers ``sub``."""
    compare = sub.add_parser(
        "compare", help="slow-flow curve (46) against the shooting branches of (9) over the same sigma range"
    )
    add_params_options(compare)
    add_range_options(compare)
    add_shooting_options(compare)
    add_sigma_points_option(compare, default=141)
    add_model_option(compare)
    compare.add_argument(
        "--impact",
        action="store_true",
        help="also the orbits of the vibro-impact model (8), from a simulation of (8) at the set's "
        "sigma: the slow flow's error against (8) "
        "(the expansion's) and (8)'s against (9) (its first-order coefficients and its wall) as "
        "columns of their own",
    )
    add_impact_model_option(compare)
    compare.set_defaults(run=_compare)
