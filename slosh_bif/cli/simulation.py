"""``slosh-bif simulate`` (a time response of (8) or (9), classified) and ``slosh-bif regimes``
(a regime map over (sigma, Abar))."""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from slosh_bif.cli.common import (
    MAX_GRID,
    Deprecated,
    abar_range,
    add_abar_range_options,
    add_backend_option,
    add_params_options,
    add_range_options,
    add_scheduler_option,
    add_tmax_option,
    cell_progress,
    check_workers,
    out_path,
    params_of,
    preset_of,
    progress,
    sigma_range,
    state0_of,
    stopped,
    sweep_executor,
    throttled,
)

__all__ = ["add_commands"]

JUDGED = 4 * np.pi  # the least run after the transient that a regime is judged over: two forcing periods


def _simulate(args) -> int:
    from slosh_bif.simulation.direct import Noise, SimulationSettings, simulate
    from slosh_bif.simulation.output import (
        plot_simulation,
        write_summary,
        write_trajectory,
    )
    from slosh_bif.simulation.regimes import RegimeSummary, classify

    preset = preset_of(args)
    params = params_of(args)
    tmax = args.tmax if args.tmax is not None else float(preset.t_window[1])
    noise = preset.noise_std if args.noise is None else args.noise
    params.require_positive_stiffness()
    if not (np.isfinite(tmax) and tmax > 0):
        raise ValueError(f"--tmax must be finite and > 0; got {tmax}")
    if args.transient is not None and not (0 <= args.transient < tmax - JUDGED):
        raise ValueError(
            f"--transient must be in [0, tmax - 4 pi = {tmax - JUDGED:g}): the regime is judged "
            f"over at least two forcing periods after it; got {args.transient}"
        )
    if args.transient is None and tmax <= 2 * JUDGED:
        raise ValueError(
            f"--tmax must be above {2 * JUDGED:.6g} (the regime is judged over the second half of "
            f"the run, at least two forcing periods of 2 pi); got {tmax:g}"
        )
    report = throttled(progress, passes=lambda message: message.startswith("simulated 100"))
    sim = simulate(
        params,
        state0_of(args, params),
        tmax,
        progress=lambda f: report(f"simulated {100 * f:.0f} % of tau in [0, {tmax:g}]"),
        settings=SimulationSettings(model=args.model, backend=args.backend),
        noise=Noise(std=noise, seed=args.seed, cutoff=args.noise_cutoff),
    )
    args.out.mkdir(parents=True, exist_ok=True)
    stopped = not sim.success and sim.status != "sticking"
    if stopped:
        print(f"slosh-bif simulate: the run stopped early (exit status 3): {sim.message}", file=sys.stderr)
    transient = args.transient if args.transient is not None and args.transient < sim.t[-1] else None
    try:
        summary = classify(sim, transient=transient)
    except ValueError:  # a run that stopped too early to be judged
        summary = RegimeSummary.failed(
            f"the run stopped at tau = {sim.t[-1]:.6g}, too early to judge: {sim.message}", math.nan
        )
    paths = [
        write_trajectory(sim, args.out / "trajectory.npz"),
        write_summary(sim, summary, args.out / "summary.json"),
        plot_simulation(
            sim,
            summary,
            args.out / "simulate.png",
            title=f"{preset.name} ({args.model} model): {summary.regime}",
        ),
    ]
    print(f"regime: {summary.regime} ({summary.reason}); {sim.message}; {sim.seconds:.2f} s")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 3 if stopped else 0  # 3: a partial result (the run to where it stopped)


def _regimes(args) -> int:
    from slosh_bif.report.files import Resume
    from slosh_bif.simulation.output import (
        plot_regime_map,
        regime_settings,
        regime_store,
        write_regime_csv,
    )
    from slosh_bif.simulation.regimes import regime_map
    from slosh_bif.simulation.settings import SimulationSettings, Workers
    from slosh_bif.slowflow.critical import critical_curve

    params = params_of(args)
    lo, hi = sigma_range(args, default=(-2.0, 4.0))
    abar_range(args, default=(args.abar_min, args.abar_max))  # 0 <= min < max, finite
    if args.grid is not None:  # the deprecated --grid N M
        args.sigma_points, args.abar_points = args.grid
    n_sigma, n_abar = args.sigma_points, args.abar_points
    if not (1 <= n_sigma <= MAX_GRID and 1 <= n_abar <= MAX_GRID):
        raise ValueError(
            f"--sigma-points and --abar-points take integers in [1, {MAX_GRID}]; got {n_sigma} and {n_abar}"
        )
    check_workers(args)
    sigmas, abars, state0 = (
        np.linspace(lo, hi, n_sigma),
        np.linspace(args.abar_min, args.abar_max, n_abar),
        state0_of(args, params),
    )
    settings = regime_settings(params, state0, sigmas, abars, tmax=args.tmax, model=args.model)
    store = regime_store(args.out / "regimes.json", settings, resume=args.resume)
    if args.resume:
        progress(
            f"resuming: {len(store.done)} of {sigmas.size * abars.size} grid points already "
            f"classified in {args.out}"
        )
    args.out.mkdir(parents=True, exist_ok=True)
    with sweep_executor(args) as executor:
        rmap = regime_map(
            params,
            state0,
            sigmas,
            abars,
            tmax=args.tmax,
            settings=SimulationSettings(model=args.model, backend=args.backend),
            workers=Workers(executor, args.workers),
            resume=Resume(store.done, store.keep),
            progress=cell_progress(progress, "grid points classified"),
        )
    store.finish(rmap.status)
    curve = (
        critical_curve(params, lo, hi) if rmap.complete else None
    )  # stopped: write what was computed, at once
    paths = [
        write_regime_csv(rmap, args.out / "regimes.csv"),
        plot_regime_map(rmap, args.out / "regimes.png", critical=curve),
    ]
    counts = {r: int(np.sum(rmap.regime == r)) for r in sorted(set(rmap.regime.ravel()))}
    print("regimes: " + ", ".join(f"{r} {c}" for r, c in counts.items()))
    print("wrote " + ", ".join(str(p) for p in paths))
    if not rmap.complete:  # the points done are written; the CLI's handler says so and exits 130 / 143
        raise stopped(rmap.status)
    return 0


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    sim = sub.add_parser(
        "simulate",
        help="time response of the smooth model (9) or the vibro-impact model (8), with its response regime",
    )
    add_params_options(sim)
    sim.add_argument(
        "--model",
        choices=("smooth", "impact", "impact-corrected"),
        default="smooth",
        help="(9) with the wall potential, (8) with impacts, or the corrected impact model (the "
        "smooth wall's own restitution at its clearance |w| = D(v)) (default smooth)",
    )
    sim.add_argument(
        "--tmax",
        type=float,
        default=None,
        help="end time tau (default: the end of the preset's figure window)",
    )
    sim.add_argument(
        "--noise",
        type=float,
        default=None,
        metavar="STD",
        help="standard deviation sigma_bar of the noise of eq. 47 (default: the preset's, 0 for most)",
    )
    sim.add_argument(
        "--seed",
        type=int,
        default=0,
        help="seed of the noise (default 0); the same seed gives the same run bit for bit",
    )
    sim.add_argument(
        "--noise-cutoff",
        type=float,
        default=10.0,
        help="highest angular frequency of the band-limited noise (default 10)",
    )
    sim.add_argument(
        "--transient",
        type=float,
        default=None,
        help="tau after which the regime is judged (default: half the run)",
    )
    add_backend_option(sim)
    sim.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    sim.set_defaults(run=_simulate)

    regimes = sub.add_parser(
        "regimes", help="map of response regimes over (sigma, Abar), simulated in parallel"
    )
    add_params_options(regimes)
    add_range_options(regimes)
    add_abar_range_options(regimes, default=(0.1, 3.0))
    regimes.add_argument("--sigma-points", type=int, default=13, help="sigma values of the grid (default 13)")
    regimes.add_argument("--abar-points", type=int, default=10, help="Abar values of the grid (default 10)")
    regimes.add_argument(
        "--grid",
        type=int,
        nargs=2,
        default=None,
        action=Deprecated,
        new="--sigma-points N --abar-points M",
        help=argparse.SUPPRESS,
    )
    add_tmax_option(regimes)
    regimes.add_argument(
        "--model", choices=("smooth", "impact"), default="smooth", help="model simulated (default smooth)"
    )
    regimes.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    add_scheduler_option(regimes)
    add_backend_option(regimes)
    regimes.add_argument(
        "--resume",
        action="store_true",
        help="reuse the cells classified in OUT/regimes.json by an earlier run with the same settings "
        "(an interrupted one) and simulate only the rest",
    )
    regimes.set_defaults(run=_regimes)
