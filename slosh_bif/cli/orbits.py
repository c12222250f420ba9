"""``slosh-bif shoot``: periodic orbits of (9) by shooting, continued, with their bifurcations."""

from __future__ import annotations

import numpy as np

from slosh_bif.cli.common import add_params_options, add_range_options, floats, params_of, progress, sigma_range, throttled
from slosh_bif.model.presets import get_preset

__all__ = ["add_commands"]


def _start_orbit(params, args):
    """A converged 2pi-orbit near --guess, or near the strobe states of a simulation from the
    preset's initial state (the last of --settle periods, then up to 49 before it)."""
    from slosh_bif.orbits.shooting import ShootingProblem, orbit_at
    from slosh_bif.simulation.integrator import integrate_grid

    problem = ShootingProblem(params, segments=args.segments)
    if args.guess is not None:
        guesses = [np.array(args.guess, dtype=float)]
    else:
        strobes = integrate_grid(params, get_preset(args.preset).state0, 2 * np.pi * np.arange(args.settle + 1))
        guesses = list(strobes[::-1][:50])
    for k, y0 in enumerate(guesses):
        orbit = orbit_at(problem, problem.initial_states(y0), params.sigma, tol=1e-9)
        if orbit.converged:
            progress(f"start orbit at sigma = {params.sigma:g}: |X(0)| = {abs(orbit.y0[0]):.4g}, multipliers |mu| = " + ", ".join(f"{abs(m):.4g}" for m in orbit.multipliers) + f" ({orbit.message})")
            return orbit.y0
    where = "--guess" if args.guess is not None else f"the last strobe states of a {args.settle}-period simulation"
    raise ValueError(f"no periodic orbit found near {where} at sigma = {params.sigma:g}; pass --guess X,Xd,w,wd or change --settle")


def family_from_args(args, params, lo, hi):
    from slosh_bif.orbits.families import trace_orbits
    from slosh_bif.orbits.starts import slow_flow_start

    if args.start == "slow-flow":
        sigma0, orbit = slow_flow_start(params, lo, hi, segments=args.segments)
        progress(f"start orbit from the slow flow at sigma = {sigma0:.5g}: |X(0)| = {abs(orbit.y0[0]):.4g} ({orbit.message})")
        params, y0 = params.replace(sigma=sigma0), orbit.y0
    else:
        y0 = _start_orbit(params, args)
    return trace_orbits(params, y0, p_min=lo, p_max=hi, segments=args.segments, switch=not args.no_switch, max_branches=args.max_branches, progress=throttled(progress))


def _shoot(args) -> int:
    from slosh_bif.orbits.output import plot_family, write_branch_csv

    params = params_of(args)
    lo, hi = sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    family = family_from_args(args, params, lo, hi)
    csv_path, png_path = write_branch_csv(family, args.out / "branch.csv"), plot_family(family, args.out / "branch.png")
    for k, ob in enumerate(family.branches):
        ob.branch.save(args.out / f"branch{k}_{ob.name}.npz")
    print(family.summary())
    print(f"wrote {csv_path}, {png_path}")
    return 0


def add_shooting_options(parser):
    parser.add_argument("--segments", type=int, default=4, help="arcs of multiple shooting per period (default 4)")
    parser.add_argument("--guess", type=floats, default=None, metavar="X,Xd,w,wd", help="state at tau = 0 near the start orbit (default: from a simulation)")
    parser.add_argument("--start", choices=("simulation", "slow-flow"), default="simulation", help="start orbit: Newton from a simulation at the preset's sigma (default), or from the leading-order motion of a stable steady state of (46) in the range (no simulation)")
    parser.add_argument("--settle", type=int, default=150, help="periods simulated from the preset's initial state for the start guess (default 150)")
    parser.add_argument("--max-branches", type=int, default=6, help="branches traced at most, the primary one included (default 6)")
    parser.add_argument("--no-switch", action="store_true", help="trace the primary branch only")


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    shoot = sub.add_parser("shoot", help="periodic orbits of the smooth model (9) by shooting, continued in sigma, with their bifurcations")
    add_params_options(shoot)
    add_range_options(shoot)
    add_shooting_options(shoot)
    shoot.set_defaults(run=_shoot)
