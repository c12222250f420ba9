"""``slosh-bif trust``, ``basins`` and ``figures``: the questions that combine the slow
flow, the orbits and the simulations over grids of sets, values and states (``compare``, one
set's: :mod:`slosh_bif.cli.compare`; a design study: :mod:`slosh_bif.cli.study`)."""

from __future__ import annotations

import sys

import numpy as np

from slosh_bif.cli.common import (
    MAX_GRID,
    add_backend_option,
    add_impact_model_option,
    add_model_option,
    add_params_options,
    add_range_options,
    add_scheduler_option,
    add_sigma_points_option,
    cell_progress,
    check_impact_model,
    check_sigma_points,
    check_workers,
    floats,
    out_path,
    params_of,
    progress,
    sigma_range,
    stopped,
    sweep_executor,
)
from slosh_bif.report.files import write_text_atomically

__all__ = ["add_commands"]


def _trust(args) -> int:
    from slosh_bif.orbits.settings import BranchingSettings, ShootingSettings
    from slosh_bif.report.files import Resume
    from slosh_bif.simulation.settings import Workers
    from slosh_bif.studies.trust import trust_map
    from slosh_bif.studies.trust_output import (
        plot_trust_map,
        trust_store,
        trust_table,
        write_trust_csv,
    )

    base = params_of(args)
    lo, hi = sigma_range(args)
    check_sigma_points(args)
    check_workers(args)
    check_impact_model(args)
    odd = [n for n in args.n if n >= 1 and (n + base.pbar) % 2]  # n < 1: Params names it
    if odd:
        raise ValueError(
            f"--n {','.join(map(str, odd))}: the wall exponent must have the parity of the set's "
            f"pbar = {base.pbar} (p = (pbar + n)/2 an integer, eq. 19)"
        )
    settings = dict(
        params=base.as_dict(),
        eps=args.eps,
        beta=args.beta,
        n=args.n,
        sigma_range=[lo, hi],
        grid=args.sigma_points,
        switch=not args.no_switch,
        max_branches=args.max_branches,
        backend=args.backend,
        model=args.model,
        # stores written without it resume as before
        **({"impact": True if args.impact_model == "paper" else args.impact_model} if args.impact else {}),
    )
    done, keep = trust_store(args.out / "trust_map.json", settings, resume=args.resume)
    if done:
        progress(f"resuming: {len(done)} parameter sets already compared in {args.out / 'trust_map.json'}")
    args.out.mkdir(parents=True, exist_ok=True)
    total = len(args.eps) * len(args.beta) * len(args.n)
    progress(
        f"{total} parameter sets, each a frequency-response curve of (46) and a family of orbits "
        "of (9) (seconds to a minute each)"
    )

    def report(point, done, total):
        progress(
            f"{done}/{total}: eps = {point.eps:g}, beta = {point.beta:g}, n = {point.n}: "
            f"{point.status}, {point.seconds:.1f} s"
        )

    with sweep_executor(args) as executor:
        points = trust_map(
            base,
            eps=args.eps,
            beta=args.beta,
            n=args.n,
            sigma_min=lo,
            sigma_max=hi,
            grid=args.sigma_points,
            shooting=ShootingSettings(backend=args.backend),
            branching=BranchingSettings(switch=not args.no_switch, max_branches=args.max_branches),
            model=args.model,
            impact=args.impact and args.impact_model,
            progress=report,
            resume=Resume(done, keep),
            workers=Workers(executor, args.workers),
        )
    table = trust_table(points, model=args.model, impact_model=args.impact_model)
    write_text_atomically(args.out / "trust_map.txt", table + "\n")
    csv_path, png_path = (
        write_trust_csv(points, args.out / "trust_map.csv"),
        plot_trust_map(points, args.out / "trust_map.png", model=args.model, impact_model=args.impact_model),
    )
    print(table)
    print(f"wrote {csv_path}, {png_path}, {args.out / 'trust_map.txt'}")
    missing = [p.status for p in points if p.status.startswith("not computed")]
    if missing:
        raise stopped(missing[0])
    failed = [p for p in points if p.status != "ok"]
    if failed:  # cells without a comparison: the map does not answer there
        print(
            f"slosh-bif trust: {len(failed)} of {len(points)} parameter set(s) not compared (their "
            "status in trust_map.csv; exit status 3)",
            file=sys.stderr,
        )
        return 3
    return 0


def _basins(args) -> int:
    from slosh_bif.studies.basins import basin_map
    from slosh_bif.studies.basins_output import (
        attractor_table,
        basin_settings,
        basin_store,
        plot_basins,
        write_attractors,
        write_basins_csv,
    )

    params = params_of(args)
    n1, n2 = args.grid
    if not (1 <= n1 <= MAX_GRID and 1 <= n2 <= MAX_GRID):
        raise ValueError(f"--grid takes two integers N M in [1, {MAX_GRID}]; got {n1} {n2}")
    for name, (lo, hi) in (("--range1", args.range1), ("--range2", args.range2)):
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ValueError(f"{name} needs finite LO < HI; got {lo} {hi}")
    check_workers(args)
    from slosh_bif.report.files import Resume
    from slosh_bif.simulation.settings import Workers
    from slosh_bif.studies.basins import BASIN_TMAX

    tmax = BASIN_TMAX if args.tmax is None else args.tmax
    if not (np.isfinite(tmax) and 0 < tmax <= 1e3 * BASIN_TMAX):
        raise ValueError(f"--tmax must be in (0, {1e3 * BASIN_TMAX:g}]; got {tmax}")
    params.require_positive_stiffness()
    first, second = np.linspace(*args.range1, n1), np.linspace(*args.range2, n2)
    store = basin_store(
        args.out / "basins.json",
        basin_settings(params, args.axes, first, second, tmax, args.model),
        resume=args.resume,
    )
    if args.resume:
        progress(f"resuming: {len(store.done)} of {n1 * n2} initial states already simulated in {args.out}")
    args.out.mkdir(parents=True, exist_ok=True)
    with sweep_executor(args) as executor:
        bmap = basin_map(
            params,
            first,
            second,
            axes=tuple(args.axes),
            tmax=tmax,
            backend=args.backend,
            model=args.model,
            workers=Workers(executor, args.workers),
            resume=Resume(store.done, store.keep),
            progress=cell_progress(progress, "initial states simulated"),
        )
    store.finish(bmap.status)
    paths = [
        write_basins_csv(bmap, args.out / "basins.csv"),
        write_attractors(bmap, args.out / "attractors.txt"),
        plot_basins(bmap, args.out / "basins.png"),
    ]
    print(attractor_table(bmap))
    print("wrote " + ", ".join(str(p) for p in paths))
    if bmap.status != "complete":
        raise stopped(bmap.status)
    return 0


def _figures(args) -> int:
    from slosh_bif.studies.figures import NOTES, make_figures

    paths = make_figures(args.out, quick=args.quick, only=args.only, progress=progress)
    for path in paths:
        print(f"{path}: {NOTES[path.stem]}")
    return 0


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    trust = sub.add_parser(
        "trust", help="compare over a grid of eps, beta and n: where the slow flow (46) can be trusted"
    )
    add_params_options(trust)
    add_range_options(trust)
    trust.add_argument(
        "--eps",
        type=floats,
        default=[0.02, 0.05, 0.1, 0.2],
        metavar="E1,E2,...",
        help="mass ratios (default 0.02,0.05,0.1,0.2)",
    )
    trust.add_argument(
        "--beta",
        type=floats,
        default=[0.0, 0.3, 0.5],
        metavar="B1,B2,...",
        help="values of beta (default 0,0.3,0.5)",
    )
    trust.add_argument(
        "--n",
        type=lambda s: [int(v) for v in s.split(",")],
        default=[6, 10, 20, 50],
        metavar="N1,N2,...",
        help="wall exponents n (default 6,10,20,50)",
    )
    add_sigma_points_option(trust, default=141)
    trust.add_argument(
        "--max-branches", type=int, default=6, help="orbit branches traced per set at most (default 6)"
    )
    trust.add_argument(
        "--no-switch",
        action="store_true",
        help="trace the primary orbit branch only (faster; misses stable asymmetric and period-2 orbits)",
    )
    trust.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    add_scheduler_option(trust)
    add_backend_option(trust)
    add_model_option(trust)
    trust.add_argument(
        "--impact",
        action="store_true",
        help="also the orbits of the vibro-impact model (8) at each set: the expansion's error "
        "((46) against (8)) and (8)'s own ((8) against (9)) apart",
    )
    add_impact_model_option(trust)
    trust.add_argument(
        "--resume",
        action="store_true",
        help="reuse the parameter sets stored in OUT/trust_map.json by an earlier run with the same "
        "settings and compute only the rest",
    )
    trust.set_defaults(run=_trust)

    basins = sub.add_parser(
        "basins",
        help="basins of attraction of (9) or (8): which response each initial state reaches, at the preset's "
        "(sigma, Abar)",
    )
    add_params_options(basins)
    basins.add_argument(
        "--grid",
        type=int,
        nargs=2,
        default=(21, 21),
        metavar=("N", "M"),
        help="initial states along the first and second axis (default 21 21)",
    )
    basins.add_argument(
        "--axes",
        nargs=2,
        default=("X", "w"),
        choices=("X", "Xd", "w", "wd"),
        metavar=("A", "B"),
        help="the state components varied (the other two start at zero; default X w)",
    )
    basins.add_argument(
        "--range1",
        type=float,
        nargs=2,
        default=(-3.0, 3.0),
        metavar=("LO", "HI"),
        help="range of the first axis (default -3 3)",
    )
    basins.add_argument(
        "--range2",
        type=float,
        nargs=2,
        default=(-1.0, 1.0),
        metavar=("LO", "HI"),
        help="range of the second axis (default -1 1, the clearance)",
    )
    basins.add_argument(
        "--tmax",
        type=float,
        default=None,
        help="the longest each start is followed, in tau (default 2,000 forcing periods; a start stops "
        "as soon as its strobe settles)",
    )
    basins.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    add_scheduler_option(basins)
    add_backend_option(basins)
    basins.add_argument(
        "--model",
        choices=("smooth", "impact", "impact-corrected"),
        default="smooth",
        help="the smooth model (9) (default), the impact model (8) on its exact flow, or the "
        "corrected impact model ((9) with its wall's own law)",
    )
    basins.add_argument(
        "--resume",
        action="store_true",
        help="reuse the initial states simulated in OUT/basins.json by an earlier run with the same "
        "settings (an interrupted one) and simulate only the rest",
    )
    basins.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    basins.set_defaults(run=_basins)

    figures = sub.add_parser("figures", help="regenerate the paper's Figs. 3-15 as PNG files (about 15 s)")
    figures.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    figures.add_argument(
        "--only", nargs="+", default=None, metavar="FIG", help="only these figures, e.g. fig10 fig11"
    )
    figures.add_argument(
        "--quick", action="store_true", help="short simulations and coarse grids (a smoke test)"
    )
    figures.set_defaults(run=_figures)
