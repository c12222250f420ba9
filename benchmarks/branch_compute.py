"""The symmetric branch of the Fig. 10 set over sigma in [-6, 8] computed in this process, by (8)
through its grazings and by (9)'s shooting: the continuation's own cost, without the interpreter,
the imports, the measures and the plot that a whole ``shoot`` process adds to both (issue 31's
speed target is a third of (9)'s; ``speed.py`` prints both ratios)."""

from __future__ import annotations

import time

from threadpoolctl import threadpool_limits

from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.families import SHOOTING_OPTIONS, trace_new_family
from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits
from slosh_bif.orbits.settings import BranchingSettings, ParameterRange, ShootingSettings
from slosh_bif.orbits.starts import start_orbit

__all__ = ["branch_seconds"]

RANGE = (-6.0, 8.0)


def _impact_branch():
    pre = get_preset("fig10")
    params = pre.params.replace(sigma=5.0)
    x0 = settled_orbit(params, pre.state0, periods=300)
    return lambda: trace_impact_orbits(params, x0, p_min=RANGE[0], p_max=RANGE[1], symmetric=True)


def _smooth_branch():
    pre = get_preset("fig10")
    start = start_orbit(pre.params, pre.state_for(pre.params), RANGE)
    return lambda: trace_new_family(
        start.params,
        start.y0,
        (),
        shooting=ShootingSettings(segments=4, rtol=1e-10, atol=1e-12),
        branching=BranchingSettings(switch=False),
        options=SHOOTING_OPTIONS,
        interval=ParameterRange(name="sigma", lo=RANGE[0], hi=RANGE[1]),
    )


def branch_seconds(repeats: int = 3) -> dict:
    """Best wall seconds of ``repeats`` runs of each branch (after one that compiles and warms the
    caches), {"impact": ..., "smooth": ...}, the runs alternating between the two, with one BLAS
    thread as the commands run."""
    with threadpool_limits(limits=1, user_api="blas"):
        runs = {"impact": _impact_branch(), "smooth": _smooth_branch()}
        for run in runs.values():
            run()
        best = {name: float("inf") for name in runs}
        for _ in range(repeats):
            for name, run in runs.items():
                start = time.perf_counter()
                run()
                best[name] = min(best[name], time.perf_counter() - start)
    return best
