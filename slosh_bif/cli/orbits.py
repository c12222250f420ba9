"""``slosh-bif shoot``: periodic orbits of (9) by shooting, or of (8) on its exact flow, continued, with their
bifurcations."""

from __future__ import annotations

import sys

from slosh_bif.cli.common import (
    abar_range,
    add_abar_range_options,
    add_backend_option,
    add_continuation_options,
    add_params_options,
    add_range_options,
    add_scheduler_option,
    continuation_options,
    floats,
    params_of,
    progress,
    sigma_range,
    state0_of,
    throttled,
)
from slosh_bif.cli.starts import check_start_inside, impact_start_of
from slosh_bif.cli.terminal import REPORTER

__all__ = ["add_commands"]


def check_family_options(args) -> float:
    """A one-line error unless the family options (shoot, compare) are usable; returns the rtol."""
    rtol = 1e-10 if args.rtol is None else args.rtol
    if not 1e-14 <= rtol <= 1e-4:
        raise ValueError(f"--rtol must be in [1e-14, 1e-4]; got {rtol}")
    for flag, value, low, high in (
        ("--segments", args.segments, 1, 64),
        ("--settle", args.settle, 0, 100_000),
        ("--max-branches", args.max_branches, 1, 1000),
        ("--scan-points", args.scan_points, 1, 1000),
        ("--scan-random", args.scan_random, 0, 1000),
    ):
        if not low <= value <= high:
            raise ValueError(f"{flag} must be an integer in [{low}, {high}]; got {value}")
    return rtol


def family_from_args(args, params, lo, hi, param="sigma"):
    """The family of orbits ``shoot`` and ``compare`` trace: from --start's orbit, over [lo, hi] of
    ``param``."""
    from slosh_bif.orbits.families import SHOOTING_OPTIONS, trace_new_family
    from slosh_bif.orbits.settings import BranchingSettings, ParameterRange, ShootingSettings
    from slosh_bif.orbits.starts import slow_flow_start, start_orbit

    rtol = check_family_options(args)
    options = continuation_options(args, SHOOTING_OPTIONS)
    if getattr(args, "resume", False) and args.start != "scan":
        raise ValueError(
            "--resume continues an interrupted --start scan; the other starts trace one family, "
            "which is not stored part by part"
        )
    shooting = ShootingSettings(segments=args.segments, rtol=rtol, atol=rtol * 1e-2, backend=args.backend)
    branching = BranchingSettings(switch=not args.no_switch, max_branches=args.max_branches)
    if args.start == "scan":
        from slosh_bif.cli.scan import scan_from_args

        tracing = dict(shooting=shooting, branching=branching, options=options)
        return scan_from_args(args, params, ParameterRange(name=param, lo=lo, hi=hi), rtol, tracing)
    if args.guess is not None:
        check_start_inside(params, param, lo, hi)
    if args.start == "slow-flow":
        start = slow_flow_start(params, lo, hi, segments=args.segments, backend=args.backend, param=param)
    else:
        try:
            start = start_orbit(
                params,
                state0_of(args, params),
                (lo, hi),
                param=param,
                settle=args.settle,
                guess=args.guess,
                segments=args.segments,
                backend=args.backend,
            )
        except RuntimeError as err:
            p0 = getattr(params, param)
            if not lo <= p0 <= hi:  # the start came from the slow flow alone
                raise ValueError(f"{err} (the set's {param} = {p0:g} lies outside the range)") from None
            where = (
                "--guess"
                if args.guess is not None
                else f"the last strobe states of a {args.settle}-period simulation"
            )
            raise ValueError(
                f"no periodic orbit found near {where} at sigma = {params.sigma:g}; pass --guess "
                "X,Xd,w,wd or change --settle"
            ) from None
    mu = ", ".join(f"{abs(m):.4g}" for m in start.orbit.multipliers)
    which = "from the slow flow " if args.start == "slow-flow" else ""
    progress(
        f"start orbit {which}at {param} = {getattr(start.params, param):.5g}: "
        f"|X(0)| = {abs(start.y0[0]):.4g}, multipliers |mu| = {mu} ({start.found_from})"
    )
    return trace_new_family(
        start.params,
        start.y0,
        (),
        shooting=shooting,
        branching=branching,
        options=options,
        progress=throttled(progress),
        found_from=start.found_from,
        interval=ParameterRange(name=param, lo=lo, hi=hi),
    )


def _shoot(args) -> int:
    from slosh_bif.orbits.criticality import family_criticality, npz_arrays, verdict_lines
    from slosh_bif.orbits.output import (
        plot_family,
        write_branch_csv,
        write_families_csv,
    )
    from slosh_bif.report.plot_process import PlotProcess
    from slosh_bif.report.tasks import scaling_line, write_tasks_csv

    params = params_of(args)
    if args.parameter == "Abar":
        lo, hi = abar_range(args, default=(0.0, 2 * params.Abar))
    else:
        lo, hi = sigma_range(args)
    if args.model != "smooth":
        return _shoot_impact(args, params, lo, hi)
    args.out.mkdir(parents=True, exist_ok=True)
    with PlotProcess() as plots:  # matplotlib imported beside the computation
        family = family_from_args(args, params, lo, hi, param=args.parameter)
        plots.submit(plot_family, family, args.out / "branch.png")
        verdicts = family_criticality(family.branches)
        csv_path = write_branch_csv(family, args.out / "branch.csv", verdicts)
        families_path = write_families_csv(family, args.out / "families.csv")
        for k, (ob, found) in enumerate(zip(family.branches, verdicts)):
            ob.branch.save(args.out / f"branch{k}_{ob.name}.npz", **npz_arrays(ob.branch, found))
        tasks_path = write_tasks_csv(family.tasks, args.out / "tasks.csv") if family.tasks else None
        png_path = plots.result()
    print(family.summary(detail=REPORTER.verbose))
    for line in verdict_lines(family, verdicts, every=REPORTER.verbose):
        print(line)
    print(
        f"wrote {csv_path}, {families_path}, {png_path}"
        + (f", {tasks_path}" if tasks_path else "")
        + (
            ""
            if REPORTER.verbose
            else " (each special point in branch.csv's 'special' column; -v lists them here)"
        )
    )
    if family.tasks:
        print(scaling_line(family.tasks, "scan"))
    return _family_status(family)


def _shoot_impact(args, params, lo, hi) -> int:
    """``shoot --model impact``: the branch of orbits of (8) through the orbit a simulation of (8)
    settles on (or --guess), across sections and grazings; a symmetric one on the half-period map,
    with the asymmetric branches born at its pitchforks (unless --no-switch)."""
    from slosh_bif.continuation import ContinuationOptions
    from slosh_bif.orbits.criticality import describe, impact_criticality, npz_arrays, phrases
    from slosh_bif.orbits.impact.output import (
        impact_rows,
        plot_impact_branch,
        write_impact_csv,
    )
    from slosh_bif.orbits.impact.problem import VARIANT_NAMES
    from slosh_bif.orbits.settings import BranchingSettings
    from slosh_bif.report.plot_process import PlotProcess
    from slosh_bif.studies.chart.impact import impact_family

    if args.start != "simulation":
        raise ValueError(
            f"--start {args.start} is for the smooth model (9); --model impact starts from a "
            "simulation of (8) or from --guess"
        )
    variant = "corrected" if args.model == "impact-corrected" else "paper"
    model_name = VARIANT_NAMES[variant]
    check_family_options(args)
    if args.guess is not None:
        check_start_inside(params, args.parameter, lo, hi)
    params.require_positive_stiffness()
    options = continuation_options(args, ContinuationOptions(step=0.05, step_max=0.3, tol=1e-10))
    args.out.mkdir(parents=True, exist_ok=True)
    with PlotProcess() as plots:  # matplotlib imported beside the computation
        at, x0 = (
            (params, args.guess) if args.guess is not None else impact_start_of(args, params, variant, lo, hi)
        )
        branching = BranchingSettings(switch=not args.no_switch, max_branches=args.max_branches)
        family = impact_family(
            at,
            x0,
            param=args.parameter,
            p_range=(lo, hi),
            branching=branching,
            options=options,
            say=progress,
            variant=variant,
        )
        branches = [(nb.name, nb.branch, nb.symmetric) for nb in family]
        verdicts = {name: impact_criticality(b, params, symmetric=half) for name, b, half in branches}
        rows = [
            r
            for name, branch, half in branches
            for r in impact_rows(
                branch, params, symmetric=half, name=name, criticality=phrases(verdicts[name])
            )
        ]
        plots.submit(plot_impact_branch, rows, params, args.out / "branch.png")
        csv_path = write_impact_csv(rows, args.out / "branch.csv")
        for name, branch, _ in branches:
            for k, piece in enumerate(branch.pieces):
                extras = dict(
                    phase=piece.phase, impacts=piece.impacts, **npz_arrays(piece.branch, verdicts[name][k])
                )
                piece.branch.save(args.out / f"{name}-piece{k}.npz", **extras)
        png_path = plots.result()
    for name, branch, _ in branches:
        part = [r for r in rows if r["branch"] == name]
        kinds = [kind for r in part for kind in r["special"].split() if kind != "END"]
        counts = (
            ", ".join(f"{kinds.count(k)} {k}" for k in ("LP", "BP", "PD", "NS", "GR") if k in kinds)
            or "no special points"
        )
        print(
            f"orbits of {model_name}, {name}: {len(part)} points in {len(branch.pieces)} pieces over "
            f"{args.parameter} in [{min(r[args.parameter] for r in part):.6g}, "
            f"{max(r[args.parameter] for r in part):.6g}], impacts per period "
            f"{sorted({r['impacts'] for r in part})}; {counts}"
        )
        for p_gr, _, _ in branch.grazing:
            print(f"  GR at {args.parameter} = {p_gr:.10g}")
        for piece, found in zip(branch.pieces, verdicts[name]):
            for k, verdict in found.items():
                sp = piece.branch.special[k]
                print(f"  {sp.kind} at {args.parameter} = {sp.p:.6g}: {describe(verdict)}")
        for end in branch.ends:
            progress(f"{name}: {end}")
    print(f"wrote {csv_path}, {png_path}")
    if not all(branch.complete for _, branch, _ in branches):
        print(
            "slosh-bif: a branch does not cover the requested range (its ends above; exit status 3)",
            file=sys.stderr,
        )
        return 3
    return 0


def _family_status(family) -> int:
    """One line per branch on stderr; exit status 3 when a branch was cut short (the requested
    range is not covered), 0 otherwise."""
    for ob in family.branches:
        b = ob.branch
        progress(f"{ob.name}: {b.status} ({b.message})")
    if not family.complete:
        cut = [ob.name for ob in family.branches if ob.branch.status != "ok"]
        print(
            f"slosh-bif: {len(cut)} branch(es) cut short ({', '.join(cut)}): the requested range "
            "is not covered (exit status 3)",
            file=sys.stderr,
        )
        return 3
    return 0


def add_shooting_options(parser):
    parser.add_argument(
        "--segments", type=int, default=4, help="arcs of multiple shooting per period (default 4)"
    )
    parser.add_argument(
        "--guess",
        type=floats,
        default=None,
        metavar="X,Xd,w,wd",
        help="state at tau = 0 near the start orbit (default: from a simulation)",
    )
    parser.add_argument(
        "--start",
        choices=("simulation", "slow-flow", "scan"),
        default="simulation",
        help="start orbit: Newton from a simulation at the preset's sigma (default; from the slow "
        "flow's states in the range where that orbit is not stable or sigma lies outside); from the "
        "leading-order motion of a stable steady state of (46) "
        "in the range (no simulation); or scan: every family that simulations from several states "
        "at several sigma, every steady state of (46) "
        "and the impact-free linear response reach, each traced once (families.csv lists them)",
    )
    parser.add_argument(
        "--scan-points",
        type=int,
        default=5,
        help="with --start scan: values of the continued parameter, evenly spread inside the range, to "
        "start from (default 5)",
    )
    parser.add_argument(
        "--scan-random",
        type=int,
        default=4,
        help="with --start scan: random initial states simulated at each of those values (default 4; "
        "drawn with --seed)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="seed of the random starts of --start scan (default 0)"
    )
    parser.add_argument(
        "--settle", type=int, default=150, help="periods simulated for a start guess (default 150)"
    )
    parser.add_argument(
        "--max-branches",
        type=int,
        default=6,
        help="branches traced at most, the primary one included (default 6)",
    )
    parser.add_argument("--no-switch", action="store_true", help="trace the primary branch only")
    add_backend_option(parser)
    add_continuation_options(
        parser,
        rtol="relative tolerance of the integration of the shooting arcs (default 1e-10; the corrector "
        "follows it)",
    )


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    shoot = sub.add_parser(
        "shoot",
        help="periodic orbits of the smooth model (9) by shooting (or of the impact model (8), --model "
        "impact), continued in sigma, with their bifurcations",
        epilog="exit status: 0 when every branch covers the requested range (or ends at a fold or closes), "
        "3 when a branch was cut short (its status in branch.csv and on stderr), 2 for bad input, "
        "1 when a method fails",
    )
    add_params_options(shoot)
    add_range_options(shoot)
    shoot.add_argument(
        "--parameter",
        choices=("sigma", "Abar"),
        default="sigma",
        help="continue in sigma (default) or in Abar at the preset's sigma",
    )
    shoot.add_argument(
        "--model",
        choices=("smooth", "impact", "impact-corrected"),
        default="smooth",
        help="smooth: orbits of (9) by multiple shooting (default); impact: orbits of the vibro-impact "
        "model (8) on its exact flow, with saltation multipliers and grazing (GR), from --start "
        "simulation or --guess; impact-corrected: the same with the smooth wall's own restitution "
        "at its clearance |w| = D(v) (the corrected impact model)",
    )
    add_abar_range_options(shoot)
    add_shooting_options(shoot)
    shoot.add_argument(
        "--resume",
        action="store_true",
        help="with --start scan: reuse the families an interrupted scan stored in OUT/scan.pickle (same "
        "settings) and trace only the rest",
    )
    shoot.add_argument(
        "--workers",
        type=int,
        default=None,
        help="with --start scan: worker processes for the starts and families (default 1: in this process); "
        "with --scheduler, tasks at once on the cluster (default: its threads); the result is the same "
        "with any number",
    )
    add_scheduler_option(shoot)
    shoot.set_defaults(run=_shoot)
