"""The global search of a frequency-response fit: starts spread over the free parameters' box
(the given start, the slow flow's estimate, seeded Latin-hypercube points), the cheap rung (the slow
flow (46)) ranking the starts the expensive one (the orbits of (9) or (8)) refines, and the best and
the runner-up minima, a runner-up within the misfit's 95 % threshold being a non-identifiability."""

from __future__ import annotations

import numpy as np

from slosh_bif.identify.response_objective import Objective
from slosh_bif.identify.response_orbits import LostOrbit
from slosh_bif.identify.response_stats import least_squares, misfit_of, search_starts, spread_starts
from slosh_bif.model.params import Params

__all__ = [
    "ORBIT_SEARCH",
    "slow_flow_estimate",
    "orbit_starts",
    "refine_start",
    "ranked_by_slow_flow",
    "runner_up",
    "minima_record",
]


def slow_flow_estimate(data, at: Params, continuous, rng, say):
    """The estimate of ``continuous`` by the slow flow (46) (eps, which does not enter it, held at
    ``at``'s), a start for an orbit fit; None where it has nothing to fit or fails. (46), not the
    corrected slow flow: the corrected one measures its wall by simulated contacts again at every
    lam or chi tried (about a second each)."""
    names = [name for name in continuous if name != "eps"]
    if not names:
        return None
    slow = Objective(data, at, names, "slowflow")
    z0 = np.array([getattr(at, name) for name in names], dtype=float)
    try:
        run = least_squares(slow, z0, rng)
    except ValueError as err:  # a slow flow without steady states near the data
        say(f"no slow-flow start: {err}")
        return None
    fitted = slow.params(run.x)
    say(f"the slow flow's estimate as a start: {', '.join(f'{n} = {getattr(fitted, n):.4g}' for n in names)}")
    return np.array([getattr(fitted, name) for name in continuous], dtype=float)


ORBIT_SEARCH = 2  # Latin-hypercube starts an orbit fit refines: the best by the slow flow's misfit


def orbit_starts(objective, z0, rng, say, extra=None, pool=None):
    """(run, objective, minima) of the best least squares from the base values, from ``extra``
    (the slow flow's estimate) where given, and from the :data:`ORBIT_SEARCH` seeded
    Latin-hypercube starts (:func:`~.response_stats.search_starts`) that the slow flow (46) ranks
    best, each with the orbits chosen afresh at its own parameters (which orbit each point follows
    is chosen where the fit starts, and different starts reach different minima): all orbits
    stable at the end first, then the least misfit; ``minima`` the (misfit, z) of every run. A
    start where an orbit cannot be found is skipped. ``pool`` (an executor: ``submit``): the starts
    run side by side on it, with the same result as one after another (each run is deterministic)."""
    inside = spread_starts(z0, objective.lower, objective.upper, factors=(1.0,))
    starts = inside + (
        spread_starts(extra, objective.lower, objective.upper, factors=(1.0,)) if extra is not None else []
    )
    starts += ranked_by_slow_flow(objective, search_starts(z0, objective.lower, objective.upper, rng))[
        :ORBIT_SEARCH
    ]
    if pool is None:
        outcomes = [refine_start(objective, start, k > 0, say) for k, start in enumerate(starts)]
    else:
        say(f"{len(starts)} starts side by side")
        futures = [pool.submit(refine_start, objective, start, k > 0) for k, start in enumerate(starts)]
        outcomes = [future.result() for future in futures]
    best, minima = None, []
    for outcome in outcomes:
        if outcome is None:
            continue
        run, here = outcome
        minima.append((misfit_of(run.fun, objective.data.std is not None), run.x))
        key = (not all(here.orbits.stable), run.cost)
        if best is None or key < best[0]:
            best = (key, run, here)
    return best[1], best[2], minima


def refine_start(objective, start, afresh: bool, say=None):
    """(run, objective at the run's end) of the least squares from ``start``, the orbits chosen
    afresh at the start's parameters where ``afresh`` ((9)'s family, traced at the base, serves
    every start); None where no orbit is found there."""
    here = objective
    if afresh:
        family = getattr(objective.orbits, "family", None)
        try:
            here = Objective(
                objective.data, objective.params(start), objective.names, objective.model, say, family
            )
        except LostOrbit:
            return None
    run = least_squares(here, start, np.random.default_rng(0), starts=1)  # one start: no draw
    here(run.x)  # the orbits at the run's end
    return run, here


def ranked_by_slow_flow(objective, starts) -> list:
    """``starts`` ordered by the misfit of the slow flow (46) at each (eps, which it does not
    contain, left out): the cheap rung ranks the starts the expensive one refines."""
    names = [name for name in objective.names if name != "eps"]
    if not names:
        return list(starts)
    slow = Objective(objective.data, objective.base, names, "slowflow")
    keep = [objective.names.index(name) for name in names]
    known = objective.data.std is not None
    return sorted(starts, key=lambda z: misfit_of(slow(np.asarray(z)[keep]), known))


def runner_up(minima, best_z, rel=1e-3):
    """(misfit, z) of the best minimum other than ``best_z`` (differing by more than ``rel`` of a
    parameter's value in some parameter), or None."""
    if best_z is None:
        return None
    scale = np.maximum(np.abs(best_z), 1e-9)
    others = [(m, z) for m, z in minima if np.max(np.abs(np.asarray(z) - best_z) / scale) > rel]
    return min(others, key=lambda mz: mz[0]) if others else None


def minima_record(names, misfit, z, runner_up) -> list:
    """The best and the runner-up minima of the global search, for fit.json."""
    rows = [{"values": {n: float(v) for n, v in zip(names, z)}, "misfit": float(misfit)}]
    if runner_up is not None:
        rows.append(
            {"values": {n: float(v) for n, v in zip(names, runner_up[1])}, "misfit": float(runner_up[0])}
        )
    return rows
