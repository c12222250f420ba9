"""``slosh-bif fit``: the wall's parameters identified from measurements (:mod:`slosh_bif.identify`),
written as fit.json, fit.png and a parameter file the other commands take with ``--params``."""

from __future__ import annotations

from pathlib import Path

from slosh_bif.cli.common import add_params_options, out_path, params_of

__all__ = ["add_commands"]


def _fit(args) -> int:
    from slosh_bif.identify import FREE_NAMES, fit_wall, read_impact_records
    from slosh_bif.identify.output import write_fit

    free = tuple(name.strip() for name in args.free.split(",") if name.strip())
    unknown = [name for name in free if name not in FREE_NAMES]
    if unknown or not free:
        raise ValueError(
            f"--free takes a comma-separated subset of {', '.join(FREE_NAMES)} (impact records "
            f"speak to the restitution law); got {args.free!r}"
        )
    base = params_of(args)
    records = read_impact_records(args.data)
    fit = fit_wall(records, base, free)
    paths = write_fit(fit, records, base, args.out)
    v = fit.values
    print(
        f"{fit.records} impact records: eq. (21) with n = {v['n']}, pbar = {v['pbar']} (q = "
        f"{fit.q:.4g}): C = {fit.C:.6g} +- {fit.C_std:.2g} "
        f"(95 %: [{fit.C_interval[0]:.6g}, {fit.C_interval[1]:.6g}]), rms residual in kappa {fit.rms:.2g}"
    )
    for name, e in fit.estimate.items():
        interval = e.get("interval_95")
        print(
            f"  {name} = {e['value']:.6g}"
            + (
                f" +- {e['std']:.2g} (95 %: [{interval[0]:.6g}, {interval[1]:.6g}])"
                if interval
                else f" ({e.get('profile', '')})"
            )
        )
    if fit.not_identifiable:
        print(f"  not identifiable: {fit.not_identifiable}")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


def add_commands(sub) -> None:
    """Register ``fit`` on the ``slosh-bif`` subparsers ``sub``."""
    fit = sub.add_parser(
        "fit",
        help="identify the wall's restitution law (lam, chi, pbar of eq. 21) from impact records, with "
        "intervals",
        epilog="data: a CSV with the columns v0 (incoming speed), v_out (outgoing speed) and optionally "
        "std (the outgoing speed's standard deviation)",
    )
    add_params_options(fit)
    fit.add_argument("--data", type=Path, required=True, help="CSV of impact records: v0, v_out[, std]")
    fit.add_argument(
        "--free",
        required=True,
        help="the parameters to fit, comma-separated: lam, chi, pbar (lam and chi together: only their "
        "combination is determined)",
    )
    fit.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    fit.set_defaults(run=_fit)
