"""``slosh-bif frc`` (the frequency response of (45), (46)) and ``slosh-bif critical`` (Abar_b(sigma))."""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.cli.common import (
    abar_range,
    add_abar_range_options,
    add_continuation_options,
    add_model_option,
    add_params_options,
    add_range_options,
    continuation_options,
    params_of,
    progress,
    sigma_range,
)

_RTOL = "Newton corrector tolerance of the continuation (default 1e-11)"


def _options(args, base):
    opts = continuation_options(args, base)
    if args.rtol is not None:
        if not 0 < args.rtol < 1e-2:
            raise ValueError(f"--rtol must be in (0, 1e-2); got {args.rtol}")
        opts = dataclasses.replace(opts, tol=args.rtol)
    return opts


__all__ = ["add_commands"]


def _frc(args) -> int:
    from slosh_bif.continuation import ContinuationOptions
    from slosh_bif.slowflow.output import plot_frc, write_frc_csv
    from slosh_bif.slowflow.steady_states import forcing_response, frequency_response

    params = params_of(args)
    if args.parameter == "Abar":
        lo, hi = abar_range(args, default=(0.0, None))
        opts = _options(args, ContinuationOptions(step=0.02, step_max=0.2))
        args.out.mkdir(parents=True, exist_ok=True)
        fr = forcing_response(params, abar_min=lo, abar_max=hi, options=opts, model=args.model)
    else:
        lo, hi = sigma_range(args)
        opts = _options(args, ContinuationOptions())
        args.out.mkdir(parents=True, exist_ok=True)
        fr = frequency_response(params, sigma_min=lo, sigma_max=hi, options=opts, model=args.model)
    if not any(len(branch) for branch in fr.branches):
        raise RuntimeError(
            f"no steady state of the slow flow over the {args.parameter} range [{lo:g}, "
            f"{hi if hi is not None else 'auto'}]: nothing to write"
        )
    csv_path, png_path = write_frc_csv(fr, args.out / "frc.csv"), plot_frc(fr, args.out / "frc.png")
    for k, branch in enumerate(fr.branches):
        branch.save(args.out / f"frc_branch{k}.npz")
        specials = ", ".join(
            f"{s.kind} at {args.parameter} = {s.p:.10g} (A = {s.x[0]:.6g})" for s in branch.special
        )
        print(f"component {k}: {len(branch)} points, {branch.message}; {specials}")
    print(f"wrote {csv_path}, {png_path}")
    return 0


def _critical(args) -> int:
    from slosh_bif.slowflow.critical import critical_curve
    from slosh_bif.slowflow.output import plot_critical, write_critical_csv

    params = params_of(args)
    lo, hi = sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    from slosh_bif.slowflow.critical import DEFAULT_OPTIONS

    curve = critical_curve(
        params, lo, hi, options=_options(args, DEFAULT_OPTIONS), progress=progress, model=args.model
    )
    csv_path, png_path = (
        write_critical_csv(curve, args.out / "critical.csv"),
        plot_critical(curve, args.out / "critical.png"),
    )
    at = (
        float(np.interp(params.sigma, curve.sigma, curve.Abar_b))
        if curve.sigma[0] <= params.sigma <= curve.sigma[-1]
        else None
    )
    if at is not None:
        verdict = (
            "steady states on S+ exist"
            if params.Abar >= at
            else "no steady state on S+ (expect a strongly modulated or non-resonant response)"
        )
        print(
            f"at the preset's sigma = {params.sigma:g}: Abar_b = {at:.6g}; Abar = {params.Abar:g}: {verdict}"
        )
    print(
        f"{len(curve.sigma)} points ({len(curve.fold_branches)} fold curve(s)); wrote {csv_path}, {png_path}"
    )
    ends = (("end-point curve", curve.end_branch), ("upper end-point curve", curve.upper_end_branch))
    for name, b in (
        *(e for e in ends if e[1] is not None),
        *((f"fold curve {k + 1}", f) for k, f in enumerate(curve.fold_branches)),
    ):
        if b.status != "ok":  # the reason a curve stopped early, not only in the npz metadata
            progress(f"{name} stopped early: {b.message}")
    return 0


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    frc = sub.add_parser(
        "frc", help="frequency-response curve A(sigma) of the slow flow by pseudo-arclength continuation"
    )
    add_params_options(frc)
    add_range_options(frc)
    frc.add_argument(
        "--parameter",
        choices=("sigma", "Abar"),
        default="sigma",
        help="continue in sigma (the frequency response, default) or in Abar at the preset's sigma",
    )
    add_abar_range_options(frc)
    add_model_option(frc)
    add_continuation_options(frc, rtol=_RTOL)
    frc.set_defaults(run=_frc)

    critical = sub.add_parser(
        "critical", help="critical forcing Abar_b(sigma) below which no steady state exists on S+"
    )
    add_params_options(critical)
    add_range_options(critical)
    add_model_option(critical)
    add_continuation_options(critical, rtol=_RTOL)
    critical.set_defaults(run=_critical)
