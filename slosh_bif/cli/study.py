"""``slosh-bif study``: a design study, one (sigma, Abar) chart of (9) or an impact model per value
of a parameter of the set or of a tank's quantity (:mod:`slosh_bif.studies.design`), on local
processes or a dask cluster, resumable."""

from __future__ import annotations

from slosh_bif.cli.chart import add_model_option
from slosh_bif.cli.common import (
    abar_range,
    add_abar_range_options,
    add_params_options,
    add_scheduler_option,
    check_workers,
    out_path,
    params_of,
    progress,
    sigma_range,
    state0_of,
    stopped,
    sweep_executor,
    throttled,
)

__all__ = ["add_commands"]


def _study(args) -> int:
    from slosh_bif.cli.chart import warn_below_box, warn_seeds
    from slosh_bif.studies.chart import ChartSettings, check_box
    from slosh_bif.studies.design import design_study, plot_study, write_study_csv

    params = params_of(args)
    name, values, at_value = _varied(args)
    slow = "slowflow" if args.model.startswith("impact") else args.model  # the slow flow drawn beside
    lo, hi = sigma_range(args)
    a_lo, a_hi = abar_range(args, default=(0.2, 2 * params.Abar))
    if args.seeds < 0:
        raise ValueError(f"--seeds must be an integer >= 0; got {args.seeds}")
    check_workers(args)
    check_box(params, (lo, hi), (a_lo, a_hi), "Abar")
    args.out.mkdir(parents=True, exist_ok=True)
    with sweep_executor(args) as executor:
        study = design_study(
            params,
            lambda at: state0_of(args, at),
            (name, values),
            box={"sigma": (lo, hi), "Abar": (a_lo, a_hi)},
            folder=args.out,
            resume=args.resume,
            settings=ChartSettings(seeds=args.seeds, workers=args.workers, executor=executor, model=slow),
            progress=throttled(progress, passes=lambda message: ": point " not in message),
            at_value=at_value,
            model=args.model if args.model.startswith("impact") else "smooth",
        )
    paths = [write_study_csv(study, args.out / "study.csv"), plot_study(study, args.out / "study.png")]
    for v in study.values:
        if v.chart is not None:
            warn_below_box(v.chart, "study", f"{name} = {v.value:.6g}: ")
            warn_seeds(v.chart, "study", f"{name} = {v.value:.6g}: ")
    for v in study.values:
        print(f"{name} = {v.value:.6g}: {v.status}" + (f" ({v.reason})" if v.reason else ""))
    print("wrote " + ", ".join(str(p) for p in paths))
    for v in study.values:
        if v.status not in ("complete", "not charted"):
            raise stopped(v.status)
    return 3 if any(v.chart is None for v in study.values) else 0


def _varied(args) -> tuple:
    """(name, values, at_value) of ``--vary``: ``at_value`` converts the --params file's tank at a
    value of one of its quantities (None for a parameter of the set)."""
    from slosh_bif.model.parameter_file import read_tank_table, tank_params
    from slosh_bif.model.params import REAL_FIELDS
    from slosh_bif.studies.design import parse_vary

    tank = None
    if getattr(args, "params", None) is not None:
        try:
            tank = read_tank_table(args.params)
        except ValueError as err:
            raise ValueError(f"--params: {err}") from None
    name, values = parse_vary(args.vary, tank)
    if tank is None or name in REAL_FIELDS:
        return name, values, None
    return name, values, lambda value: tank_params({**tank, name: value}).with_overrides(args.overrides)


def add_commands(sub) -> None:
    """Register ``study`` on the ``slosh-bif`` subparsers ``sub``."""
    study = sub.add_parser(
        "study",
        help="a design study: one (sigma, Abar) chart of (9) (or, --model, of an impact model) per value "
        "of a third parameter, and how the critical forcing and the way it is lost move with it",
        epilog="exit status: 0 when every value was charted, 3 when a value was not (its reason in "
        "study.csv), 2 for bad input, 130/143 when interrupted (--resume continues)",
    )
    add_params_options(study)
    study.add_argument(
        "--vary",
        required=True,
        metavar="NAME=LO:HI:COUNT",
        help="the parameter and its values, e.g. beta=0.1:0.5:5, or a quantity of the --params file's "
        "[tank] table, e.g. depth=0.2:0.5:4 (m)",
    )
    study.add_argument(
        "--sigma-min", type=float, default=None, help="lower end of the sigma range (default -6)"
    )
    study.add_argument(
        "--sigma-max", type=float, default=None, help="upper end of the sigma range (default 8)"
    )
    add_abar_range_options(study)
    study.add_argument(
        "--seeds", type=int, default=7, help="primary-branch orbits continued in Abar per chart (default 7)"
    )
    study.add_argument(
        "--workers",
        type=int,
        default=None,
        help="worker processes (default: one per core); with --scheduler, curves at once on the cluster",
    )
    add_scheduler_option(study)
    add_model_option(study)
    study.add_argument(
        "--resume", action="store_true", help="reuse the curves an interrupted run stored in --out"
    )
    study.add_argument(
        "--out", type=out_path, required=True, help="folder for study.csv, study.png and the charts"
    )
    study.set_defaults(run=_study)
