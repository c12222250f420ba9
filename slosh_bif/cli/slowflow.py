"""``slosh-bif frc`` (the frequency response of (45), (46)) and ``slosh-bif critical`` (Abar_b(sigma))."""

from __future__ import annotations

import numpy as np

from slosh_bif.cli.common import add_params_options, add_range_options, params_of, progress, sigma_range

__all__ = ["add_commands"]


def _frc(args) -> int:
    from slosh_bif.slowflow.output import plot_frc, write_frc_csv
    from slosh_bif.slowflow.steady_states import frequency_response

    params = params_of(args)
    lo, hi = sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    fr = frequency_response(params, sigma_min=lo, sigma_max=hi)
    csv_path, png_path = write_frc_csv(fr, args.out / "frc.csv"), plot_frc(fr, args.out / "frc.png")
    for k, branch in enumerate(fr.branches):
        branch.save(args.out / f"frc_branch{k}.npz")
        specials = ", ".join(f"{s.kind} at sigma = {s.p:.10g} (A = {s.x[0]:.6g})" for s in branch.special)
        print(f"component {k}: {len(branch)} points, {branch.message}; {specials}")
    print(f"wrote {csv_path}, {png_path}")
    return 0


def _critical(args) -> int:
    from slosh_bif.slowflow.critical import critical_curve
    from slosh_bif.slowflow.output import plot_critical, write_critical_csv

    params = params_of(args)
    lo, hi = sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    curve = critical_curve(params, lo, hi, progress=progress)
    csv_path, png_path = write_critical_csv(curve, args.out / "critical.csv"), plot_critical(curve, args.out / "critical.png")
    at = float(np.interp(params.sigma, curve.sigma, curve.Abar_b)) if curve.sigma[0] <= params.sigma <= curve.sigma[-1] else None
    if at is not None:
        verdict = "steady states on S+ exist" if params.Abar >= at else "no steady state on S+ (expect a strongly modulated or non-resonant response)"
        print(f"at the preset's sigma = {params.sigma:g}: Abar_b = {at:.6g}; Abar = {params.Abar:g}: {verdict}")
    print(f"{len(curve.sigma)} points ({len(curve.fold_branches)} fold curve(s)); wrote {csv_path}, {png_path}")
    return 0


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    frc = sub.add_parser("frc", help="frequency-response curve A(sigma) of the slow flow by pseudo-arclength continuation")
    add_params_options(frc)
    add_range_options(frc)
    frc.set_defaults(run=_frc)

    critical = sub.add_parser("critical", help="critical forcing Abar_b(sigma) below which no steady state exists on S+")
    add_params_options(critical)
    add_range_options(critical)
    critical.set_defaults(run=_critical)
