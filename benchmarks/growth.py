"""The cost of growth: a branch and a fixed simulation as the wall exponent n grows, simulation
time against interval length, regime-map time against grid size and worker processes.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from benchmarks.frequency_response import REFERENCE_SEGMENTS
from benchmarks.timing import PERIOD, timed
from slosh_bif.continuation import continuation
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.families import SHOOTING_OPTIONS
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import settle_and_shoot
from slosh_bif.simulation.direct import SimulationSettings, simulate
from slosh_bif.simulation.regimes import regime_map
from slosh_bif.simulation.settings import Workers
from slosh_bif.slowflow.flow import AsymptoticsWarning
from slosh_bif.slowflow.steady_states import frequency_response

# --- the cost of growth ----------------------------------------------------------------------------

GROWTH_N = (6, 10, 20, 50)
BRANCH_RANGE = (4.0, 10.0)  # stable symmetric orbits at sigma = 4 for every n of GROWTH_N (Abar = 3)


def _shooting_start(params, state0, sigma):
    """A ShootingProblem and a 2pi-orbit of (9) at ``sigma``, from a settled simulation."""
    start_params = params.replace(sigma=sigma)
    orbit, _ = settle_and_shoot(start_params, state0, 1e-10, segments=REFERENCE_SEGMENTS)
    if not orbit.converged:
        raise RuntimeError(f"no start orbit at sigma = {sigma}, n = {params.n}: {orbit.message}")
    problem = ShootingProblem(start_params, segments=REFERENCE_SEGMENTS)
    return problem, problem.initial_states(orbit.y0)


def growth_bench(*, quick: bool = False, repeats: int = 3, progress=None):
    """Rows ``(study, x, method, seconds, detail)`` for the growth studies."""
    say = progress or (lambda message: None)
    pre = get_preset("fig10")
    rows = []
    rep = 1 if quick else repeats
    for n in GROWTH_N[::3] if quick else GROWTH_N:
        params = pre.params.replace(n=n)
        say(f"growth: n = {n}")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AsymptoticsWarning)
            seconds, fr, _ = timed(
                lambda: frequency_response(params, sigma_min=-6.0, sigma_max=8.0),
                repeats=rep,
                min_seconds=0.0,
            )
        rows.append(
            dict(
                study="n",
                x=n,
                method="eq. 46 branch, sigma in [-6, 8]",
                seconds=seconds,
                detail=f"{sum(len(b) for b in fr.branches)} points",
            )
        )
        problem, x0 = _shooting_start(params, pre.state0, BRANCH_RANGE[0])
        options = dataclasses.replace(
            SHOOTING_OPTIONS, p_min=BRANCH_RANGE[0], p_max=BRANCH_RANGE[1], direction="forward"
        )
        seconds, branch, _ = timed(
            lambda: continuation(problem, x0, BRANCH_RANGE[0], param="sigma", options=options),
            repeats=rep,
            min_seconds=0.0,
        )
        specials = " ".join(f"{sp.kind} {sp.p:.4g}" for sp in branch.special)
        rows.append(
            dict(
                study="n",
                x=n,
                method="shooting branch (9), sigma 4 -> 10",
                seconds=seconds,
                detail=f"{len(branch)} points; {specials}",
            )
        )
        seconds, sim, _ = timed(
            lambda: simulate(params, pre.state0, 100 * PERIOD), repeats=rep, min_seconds=0.0
        )
        rows.append(
            dict(study="n", x=n, method="smooth model (9), 100 periods", seconds=seconds, detail=sim.status)
        )
    for periods in (25, 100) if quick else (25, 50, 100, 200, 400):
        say(f"growth: interval of {periods} periods")
        for model in ("smooth", "impact"):
            seconds, sim, _ = timed(
                lambda: simulate(
                    pre.params,
                    pre.state0,
                    periods * PERIOD,
                    settings=SimulationSettings(model=model, sample_step=0.05),
                ),
                repeats=rep,
                min_seconds=0.0,
            )
            rows.append(
                dict(
                    study="interval",
                    x=periods,
                    method=f"{model} model simulated",
                    seconds=seconds,
                    detail=f"{len(sim.impact_t)} impacts",
                )
            )
    sides = (2, 3) if quick else (2, 3, 4, 6)
    for workers in (1, 2):
        for side in sides:
            say(f"growth: regime map {side} x {side}, {workers} worker(s)")
            sigmas, abars = np.linspace(-2.0, 4.0, side), np.linspace(0.5, 3.0, side)
            seconds, _, _ = timed(
                lambda: regime_map(
                    pre.params,
                    pre.state0,
                    sigmas,
                    abars,
                    tmax=60 * PERIOD,
                    workers=Workers(max_workers=workers),
                ),
                repeats=1,
                min_seconds=0.0,
            )
            rows.append(
                dict(
                    study="regime map",
                    x=side * side,
                    method=f"{workers} worker{'s' if workers > 1 else ''}",
                    seconds=seconds,
                    detail="60 periods per point",
                )
            )
    return rows
