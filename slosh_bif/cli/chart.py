"""``slosh-bif chart``: the curves in (sigma, Abar) where the periodic orbits of (9) fold or
double their period, the full model's critical forcing read off them, and the slow flow's
Abar_b beside it (optionally over a simulated regime map)."""

from __future__ import annotations

import sys

import numpy as np

from slosh_bif.cli.common import (
    abar_range,
    add_abar_range_options,
    add_backend_option,
    add_params_options,
    add_scheduler_option,
    add_tmax_option,
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
from slosh_bif.model.params import REAL_FIELDS

__all__ = ["add_commands"]


def _chart(args) -> int:
    with sweep_executor(args) as executor:
        return _chart_on(args, executor)


def _chart_on(args, executor) -> int:
    from slosh_bif.report.files import Resume
    from slosh_bif.report.tasks import scaling_line, write_tasks_csv
    from slosh_bif.studies.chart import check_box
    from slosh_bif.studies.chart.output import (
        chart_settings,
        curve_store,
        plot_chart,
        write_codim2_csv,
        write_critical_csv,
        write_curves_csv,
    )

    params = params_of(args)
    lo, hi = sigma_range(args)
    if args.second == "Abar":
        if args.second_min is not None or args.second_max is not None:
            raise ValueError(
                "--second-min/--second-max go with --second NAME other than Abar; Abar's range is "
                "--abar-min/--abar-max"
            )
        a_lo, a_hi = abar_range(args, default=(0.2, 2 * params.Abar))
    else:
        if args.abar_min is not None or args.abar_max is not None or args.regimes is not None:
            raise ValueError(
                "--abar-min, --abar-max and --regimes belong to the (sigma, Abar) chart; with "
                f"--second {args.second} give --second-min and --second-max"
            )
        if args.second_min is None or args.second_max is None:
            raise ValueError(f"--second {args.second} needs its range: --second-min and --second-max")
        a_lo, a_hi = args.second_min, args.second_max
        check_box(params, (lo, hi), (a_lo, a_hi), args.second)
    if args.regimes is not None:
        from slosh_bif.simulation.regimes import check_run_length

        if min(args.regimes) < 1:
            raise ValueError(
                f"--regimes takes two positive integers N M (sigma values, Abar values); got {args.regimes}"
            )
        check_run_length(args.tmax)  # before the curves, not minutes later when the map starts
    if args.seeds < 0:
        raise ValueError(f"--seeds must be an integer >= 0; got {args.seeds}")
    check_workers(args)
    impact = args.model in ("impact", "impact-corrected")
    if impact and args.second != "Abar":
        raise ValueError(
            f"--model {args.model} draws the (sigma, Abar) chart of an impact model: without --second"
        )
    if impact and args.backend != "auto" and args.regimes is None:
        raise ValueError(
            "--backend chooses the integrator of (9), or with --model impact that of --regimes' simulations; "
            "the orbits of the impact models have one exact flow"
        )
    if args.model == "impact-corrected" and args.regimes is not None:
        raise ValueError(
            "--regimes simulates (9) or (8); with --model impact-corrected, draw them with --model impact "
            "or without --model"
        )
    state0 = state0_of(args, params)
    options = dict(switch=not args.no_switch, seeds=args.seeds, backend=args.backend)
    if args.second != "Abar":  # (a stored Abar chart's settings stay as they were: --resume keeps working)
        options["second"] = args.second
    if impact:
        options["model"] = args.model
    settings = chart_settings(params, state0, (lo, hi), (a_lo, a_hi), **options)
    done, keep = curve_store(args.out / "curves", settings, resume=args.resume)
    say = throttled(progress, passes=lambda message: ": point " not in message)
    shared = _shared_pool(args, executor)
    own = shared is not None and shared is not executor  # local processes this command stops
    executor = executor if shared is None else shared
    box = (lo, hi, a_lo, a_hi)
    try:
        pending = _submit_regimes(args, params, state0, box, executor) if shared is not None else None
        chart = _trace_chart(args, params, state0, box, executor, say, Resume(done, keep))
        regimes = None
        if args.regimes is not None and chart.status == "complete":
            if pending is None:  # after the curves, on the map's own local processes
                pending = _submit_regimes(args, params, state0, box, executor)
            regimes = pending.result(
                lambda done, total, report=throttled(progress, passes=lambda message: False): report(
                    f"regimes: {done} of {total}"
                )
            )
        elif pending is not None:
            pending.cancel()
    except BaseException:
        if own:
            shared.stop()
        raise
    if own:  # an interrupted map or chart leaves running tasks: stopped, not waited for
        finished = chart.status == "complete" and (regimes is None or regimes.status == "complete")
        if finished:
            shared.close()
        else:
            shared.stop()
    paths = [write_curves_csv(chart, args.out / "curves.csv")]
    if chart.reads_critical:
        paths.append(write_critical_csv(chart, args.out / "critical.csv"))
    else:  # not an earlier run's left beside this one's curves
        (args.out / "critical.csv").unlink(missing_ok=True)
    paths.append(write_codim2_csv(chart, args.out / "codim2.csv"))
    paths.append(plot_chart(chart, args.out / "chart.png", regimes=regimes))
    paths.append(write_tasks_csv(chart.tasks, args.out / "tasks.csv"))
    for k, c in enumerate(chart.curves):
        codim2 = ", ".join(f"{label} ({sigma:.5g}, {abar:.5g})" for label, sigma, abar in c.codim2_points())
        print(
            f"curve {k}: {c.kind} from {c.origin}: {len(c)} points, {c.status}"
            + (f"; {codim2}" if codim2 else "")
        )
    print(f"{len(chart.curves)} curves in {chart.seconds:.1f} s; wrote " + ", ".join(str(p) for p in paths))
    print(scaling_line(chart.tasks))
    warn_below_box(chart, "chart")
    warn_seeds(chart, "chart")
    for status in (chart.status, regimes.status if regimes is not None else "complete"):
        if status != "complete":  # the files hold what was finished
            raise stopped(status)
    if chart.incomplete:
        for line in chart.incomplete:
            print(f"slosh-bif chart: {line}", file=sys.stderr)
        print(
            f"slosh-bif chart: {len(chart.incomplete)} curve(s) cut short or not started (their "
            "status in curves.csv)",
            file=sys.stderr,
        )
        return 3
    return 0


def _shared_pool(args, executor):
    """The executor that the regime map and the curves share, so that the map's cells run while
    this process traces the orbit family and fill the workers beside the curves: the cluster's,
    or local processes (``--workers``, one per core by default); None without ``--regimes`` or
    with one local worker (the map then runs after the curves, as before)."""
    if args.regimes is None:
        return None
    if executor is not None:
        return executor
    from slosh_bif.simulation.sweep import WorkerPool
    from slosh_bif.studies.chart.result import chart_workers

    return WorkerPool(args.workers) if chart_workers(args.workers) > 1 else None


def _submit_regimes(args, params, state0, box, executor):
    """The ``--regimes`` map's cells submitted to ``executor`` (None: its own local processes)."""
    from slosh_bif.simulation.regimes import submit_regime_map
    from slosh_bif.simulation.settings import SimulationSettings, Workers

    lo, hi, a_lo, a_hi = box
    n, m = args.regimes
    return submit_regime_map(
        params,
        state0,
        np.linspace(lo, hi, n),
        np.linspace(a_lo, a_hi, m),
        tmax=args.tmax,
        workers=Workers(executor, args.workers),
        settings=SimulationSettings(
            model="impact" if args.model == "impact" else "smooth", backend=args.backend
        ),
    )


def _trace_chart(args, params, state0, box, executor, say, resume):
    """The chart of (9) or of an impact model over ``box`` (lo, hi, a_lo, a_hi), the curves on
    ``executor``."""
    from slosh_bif.orbits.settings import BranchingSettings, ShootingSettings
    from slosh_bif.studies.chart import ChartSettings, bifurcation_chart

    lo, hi, a_lo, a_hi = box
    branching = BranchingSettings(switch=not args.no_switch)
    if args.model in ("impact", "impact-corrected"):
        from slosh_bif.studies.chart.impact import impact_chart

        return impact_chart(
            params,
            state0,
            sigma_range=(lo, hi),
            abar_range=(a_lo, a_hi),
            branching=branching,
            settings=ChartSettings(seeds=args.seeds, workers=args.workers, executor=executor),
            progress=say,
            variant="corrected" if args.model == "impact-corrected" else "paper",
            resume=resume,
        )
    return bifurcation_chart(
        params,
        state0,
        box={"sigma": (lo, hi), args.second: (a_lo, a_hi)},
        shooting=ShootingSettings(backend=args.backend),
        branching=branching,
        settings=ChartSettings(seeds=args.seeds, workers=args.workers, model=args.model, executor=executor),
        progress=say,
        resume=resume,
    )


def add_commands(sub) -> None:
    """Register ``chart`` on the ``slosh-bif`` subparsers ``sub``."""
    chart = sub.add_parser(
        "chart",
        help="curves in (sigma, Abar) where the orbits of (9) fold or period-double, and the full "
        "model's critical forcing",
        epilog="exit status: 0 when every curve left the box, closed or reached a strong resonance, 3 "
        "when a curve was cut short, 2 for bad input, 130/143 when interrupted (the finished "
        "curves are written; critical.csv only when every curve is)",
    )
    add_params_options(chart)
    chart.add_argument(
        "--sigma-min", type=float, default=None, help="lower end of the sigma range (default -6)"
    )
    chart.add_argument(
        "--sigma-max", type=float, default=None, help="upper end of the sigma range (default 8)"
    )
    add_abar_range_options(chart)
    chart.add_argument(
        "--second",
        default="Abar",
        choices=tuple(name for name in REAL_FIELDS if name != "sigma"),
        help="the chart's second parameter (default Abar); another one takes its range from "
        "--second-min/--second-max, and the chart then has no critical forcing",
    )
    chart.add_argument(
        "--second-min",
        type=float,
        default=None,
        help="lower end of the second parameter's range (with --second other than Abar)",
    )
    chart.add_argument(
        "--second-max",
        type=float,
        default=None,
        help="upper end of the second parameter's range (with --second other than Abar)",
    )
    chart.add_argument(
        "--regimes",
        type=int,
        nargs=2,
        default=None,
        metavar=("N", "M"),
        help="also simulate an N x M regime map as background",
    )
    add_tmax_option(chart)
    chart.add_argument("--no-switch", action="store_true", help="the curves of the primary orbit branch only")
    chart.add_argument(
        "--seeds",
        type=int,
        default=7,
        help="sigma values at which the primary branch's orbit is also continued in Abar (or --second) "
        "to find folds and period doublings off the preset's value; where the primary branch does not "
        "reach, their share of the rest of the box is searched for orbits of its own (default 7)",
    )
    add_backend_option(chart)
    chart.add_argument(
        "--resume",
        action="store_true",
        help="reuse the curves stored in OUT/curves/ by an earlier run with the same settings (an "
        "interrupted one) and trace only the rest",
    )
    chart.add_argument(
        "--workers",
        type=int,
        default=None,
        help="processes tracing curves (and the regime map) side by side (default: one per core); "
        "with --scheduler, curves at once on the cluster (default: its threads)",
    )
    add_scheduler_option(chart)
    chart.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    add_model_option(chart)
    chart.set_defaults(run=_chart)


def add_model_option(parser) -> None:
    """``--model``: whose curves a chart draws (``chart``, and each chart of ``study``)."""
    parser.add_argument(
        "--model",
        choices=("slowflow", "corrected", "impact", "impact-corrected"),
        default="slowflow",
        help="curves of (9) with the slow flow (46) beside them (default) or the corrected slow flow "
        "('corrected'); 'impact': the curves of the impact model (8) (from its branches in sigma), "
        "with (46) beside them; 'impact-corrected': those of the corrected impact model ((9)'s "
        "flights, its wall's measured law)",
    )


def warn_below_box(chart, command: str, where: str = "") -> None:
    """A warning on stderr for each curve of ``chart`` that bounds stable orbits and leaves
    through the box's lowest Abar (``where``: which chart of several, as "beta = 0.3: ")."""
    from slosh_bif.studies.chart.reading import exits_below

    for k, kind, sigma, _ in exits_below(chart):
        print(
            f"slosh-bif {command}: warning: {where}curve {k} ({kind}) bounds stable orbits where it leaves "
            f"the box at Abar = {chart.abar_range[0]:g}, sigma = {sigma:.5g}: beyond it the least stable "
            "forcing may lie below the box (below_box in the CSV); lower --abar-min to see it",
            file=sys.stderr,
        )


def warn_seeds(chart, command: str, where: str = "") -> None:
    """A warning on stderr for each seed of ``chart`` whose branches in Abar have stable orbits
    with wall contact below what the curves read there (:func:`seed_disagreements`)."""
    from slosh_bif.studies.chart.reading import seed_disagreements

    for sigma, read, least, below in seed_disagreements(chart):
        there = "down to the box's bottom" if below else f"down to Abar = {least:.6g}"
        read_there = f"{where}at sigma = {sigma:.5g} the curves read Abar_c = {read:.6g}"
        missed = f"stable orbits with wall contact {there}: a boundary the curves miss"
        ask = (
            "; `slosh-bif answer critical-forcing` at that sigma asks every family"
            if chart.orbits == "(9)"
            else ""
        )
        print(
            f"slosh-bif {command}: warning: {read_there}, but the branches in Abar there have {missed}{ask}",
            file=sys.stderr,
        )
