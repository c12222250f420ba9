"""Families the one-parameter trace misses at a trust-map point: isolas and detached branches of (9),
looked for where the slow flow (46) has a stable state that no traced orbit matches, from
simulations settled near it."""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.model.params import Params
from slosh_bif.orbits.families import SHOOTING_OPTIONS, trace_new_family
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.settings import (
    NO_SWITCHING,
    SHOOTING,
    ParameterRange,
    ShootingSettings,
)
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import (
    orbit_from_simulation,
    orbit_from_slow_flow,
)
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.studies.compare import compare_rows, orbits_at

__all__ = [
    "ISOLA_OPTIONS",
    "ISOLA_TRIES",
    "SETTLE_PERIODS",
    "missed_families",
]


ISOLA_TRIES = 4
"""Newton starts of (9) per parameter set from stable slow-flow states no traced orbit matches: a
family on an isola (the Fig. 13 set at n = 6: stable impacting orbits at sigma in [-2, -1] apart
from the symmetric branch) is found from one, and each costs a shooting Newton (~0.1-1 s)."""


SETTLE_PERIODS = 150
"""Where Newton from a slow-flow state fails, (9) is simulated from it this long and Newton tried
from its last strobes (the Fig. 13 set at n = 6, beta = 0.3: a stable family 23-29 % from the
corrected flow's states that Newton from them missed; 150 periods cost 3-30 ms)."""


ISOLA_OPTIONS = dataclasses.replace(SHOOTING_OPTIONS, max_steps=600)
"""A missed family is continued for 600 points a direction at most (one at eps = 0.05, beta = 0.5,
n = 50 crept on for minutes): what it traced by then is kept. A count, not a time, so that
the trust map does not depend on the machine's load."""


def missed_families(
    params: Params,
    fr,
    family,
    sigmas,
    *,
    model: str = "slowflow",
    agree_within: float = 0.05,
    tries: int = ISOLA_TRIES,
    shooting: ShootingSettings = SHOOTING,
) -> list:
    """OrbitBranches of (9) that ``family`` (continued from one start) does not contain, found by
    Newton from the slow flow's motion at up to ``tries`` of the stable states of ``fr`` on the
    grid ``sigmas`` that have no orbit of ``family`` within ``agree_within`` (where Newton fails,
    from the last strobes of a simulation of (9) settled from that motion over
    ``SETTLE_PERIODS`` periods, when it settles), and continued in sigma
    over the grid's range (no switching). An orbit whose A1 equals one already traced there (to
    1e-6) is not traced again; a start where Newton or the continuation fails is passed over:
    the comparison then measures against the orbits that were found."""
    if not (isinstance(tries, int) and tries >= 0):
        raise ValueError(f"tries must be an integer >= 0; got {tries!r}")
    if tries == 0:
        return []
    lo, hi = float(np.min(sigmas)), float(np.max(sigmas))
    lonely = [
        r
        for r in compare_rows(family, fr, sigmas)
        if r["slow_flow_stable"] and not r["relative_difference"] <= agree_within
    ]
    found = []
    for row in lonely[:: max(1, len(lonely) // tries)][:tries]:
        sigma, A = row["sigma"], row["A_slow_flow"]
        at = params.replace(sigma=sigma)
        psi = _phase_near(fr, sigma, A)
        try:
            orbit = orbit_from_slow_flow(
                at, A, psi=psi, segments=shooting.segments, backend=shooting.backend, model=model
            )
            how = "Newton from a slow-flow state no traced orbit matched"
            if not orbit.converged:  # let (9) settle from the slow flow's motion, and Newton from there
                state = SlowFlow(at, model).fast_state(A, psi, np.zeros(1)).ravel()
                orbit = orbit_from_simulation(
                    at,
                    state,
                    settle=SETTLE_PERIODS,
                    segments=shooting.segments,
                    tries=5,
                    backend=shooting.backend,
                    unsettled="raise",
                ).orbit
                how = (
                    f"Newton from a {SETTLE_PERIODS}-period simulation settled from a slow-flow state "
                    "no traced orbit matched"
                )
            problem = ShootingProblem(at, segments=shooting.segments, backend=shooting.backend)
            A1 = orbit_measures(problem, problem.initial_states(orbit.y0), sigma)["A1"]
            if any(abs(a - A1) <= 1e-6 * A1 for a, _, _ in orbits_at(family.branches + found, sigma)):
                continue
            more = trace_new_family(
                at,
                orbit.y0,
                family.branches + found,
                shooting=shooting,
                branching=NO_SWITCHING,
                options=ISOLA_OPTIONS,
                found_from=how,
                interval=ParameterRange(name="sigma", lo=lo, hi=hi),
            )
        except (RuntimeError, ValueError):  # ConvergenceError included: this start found nothing
            continue
        found.extend(more.branches)
    return found


def _phase_near(fr, sigma, A) -> float:
    """psi of the point of ``fr``'s branches nearest to (sigma, A): a Newton guess's phase."""
    return min(
        (
            (float(np.hypot(b.p[i] - sigma, b.x[i, 0] - A)), float(b.x[i, 1]))
            for b in fr.branches
            for i in range(len(b))
        )
    )[1]
