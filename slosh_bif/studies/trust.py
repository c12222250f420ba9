"""Where the slow flow can be trusted: eq. (46) against periodic orbits of (9) over eps, beta, n.

For one parameter set, :func:`trust_point` traces the frequency-response curve of (46) and the
2pi-orbits of the smooth model (9) over the same sigma range (the family started from a stable
steady state of (46), :func:`~slosh_bif.orbits.slow_flow_start`, then switched at its branch
points and period doublings), compares them on a sigma grid
(:func:`~slosh_bif.orbits.output.compare_rows`) and keeps four numbers about the slow flow's
*stable* states:

* ``agree``: the fraction within ``agree_within`` (relative) of the first-harmonic amplitude A1
  of some 2pi-orbit of (9) (the slow flow describes an orbit that exists);
* ``confirmed``: the fraction within ``agree_within`` of a *stable* 2pi-orbit (what a simulation
  of (9) would settle on: the slow flow's prediction is what one sees);
* ``median_difference``, ``max_difference``: of |A1 - A| / A to the nearest orbit.

:func:`trust_map` runs it over a grid of (eps, beta, n) around a base parameter set, in a process
pool. Each point also records whether :class:`~slosh_bif.slowflow.flow.AsymptoticsWarning` would
fire there, so the map checks the warning's thresholds.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import time
import warnings

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import check_model
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.settings import (
    BRANCHING,
    SHOOTING,
    BranchingSettings,
    ParameterRange,
    ShootingSettings,
)
from slosh_bif.orbits.starts import (
    slow_flow_start,
)
from slosh_bif.report.files import Resume
from slosh_bif.simulation.settings import LOCAL, Workers
from slosh_bif.simulation.sweep import run_cells
from slosh_bif.slowflow.flow import AsymptoticsWarning, asymptotics_concerns
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies.compare import compare_rows, impact_branch_rows, impact_errors
from slosh_bif.studies.isolas import ISOLA_TRIES, missed_families

__all__ = ["TrustPoint", "trust_point", "trust_map", "TRUST_COLUMNS"]

TRUST_COLUMNS = (
    "eps",
    "beta",
    "n",
    "stable_states",
    "agree",
    "confirmed",
    "median_difference",
    "max_difference",
    "warned",
    "sigma_start",
    "branches",
    "seconds",
    "status",
    "impact_measured",
    "asymptotic_median",
    "asymptotic_max",
    "wall_median",
    "wall_max",
    "impact_status",
)


@dataclasses.dataclass(frozen=True)
class TrustPoint:
    """The slow flow against (9) at one (eps, beta, n); see the module docstring for the measures.

    Attributes
    ----------
    stable_states : int
        Stable slow-flow states on the sigma grid (the denominator).
    warned : bool
        Whether AsymptoticsWarning fires at these parameters.
    sigma_start : float
        Where the orbit family was started.
    branches : int
        How many orbit branches were traced.
    status : str
        "ok", or why there is nothing to compare (no steady state, no orbit found, no orbit at
        the sigma of any stable state).
    impact_measured, asymptotic_median, asymptotic_max, wall_median, wall_max, impact_status
        With the orbits of (8) (``impact=True``): over the stable states that have a stable orbit
        of (8) and one of (9) nearby (``impact_measured`` of them), the expansion's error ((46)
        against (8)) and the wall's ((8) against (9)), median and largest; ``impact_status`` "ok"
        or why (8) was not measured ("" when not asked).
    """

    eps: float
    beta: float
    n: int
    stable_states: int
    agree: float
    confirmed: float
    median_difference: float
    max_difference: float
    warned: bool
    sigma_start: float
    branches: int
    seconds: float
    status: str
    impact_measured: int = 0
    asymptotic_median: float = float("nan")
    asymptotic_max: float = float("nan")
    wall_median: float = float("nan")
    wall_max: float = float("nan")
    impact_status: str = ""

    def as_row(self) -> dict:
        return dataclasses.asdict(self)


# starts of the family from the slow flow, tried in turn while the continuation fails from them
START_TRIES = 3


def trust_point(
    params: Params,
    sigma_min: float = -6.0,
    sigma_max: float = 8.0,
    *,
    grid: int = 141,
    agree_within: float = 0.05,
    shooting: ShootingSettings = SHOOTING,
    branching: BranchingSettings = BRANCHING,
    model: str = "slowflow",
    isola_tries: int = ISOLA_TRIES,
    impact: bool = False,
) -> TrustPoint:
    """Compare (46) with the 2pi-orbits of (9) over [sigma_min, sigma_max] at ``params``.

    The orbits are the family continued from one start, and the families found from the slow
    flow's stable states that no orbit of it matches (:func:`missed_families`, ``isola_tries``
    of them at most). Never raises for a parameter set where the comparison cannot be made:
    ``status`` says why.
    ``shooting``: how the orbits of (9) are computed; ``branching``: which branches the family
    follows beyond the first. ``model``: the slow flow
    compared (the paper's or the corrected one); the family is started from the paper's slow flow
    with either, the missed families are searched from the compared model's own states (a model
    is measured against every orbit near its states that Newton finds). ``impact``: also the
    orbits of (8) (from a simulation of (8) started on the family's first orbit), so that the
    expansion's error and (8)'s own are measured apart (``"corrected"``: of the corrected impact
    model instead, whose difference to (9) is the contact's duration alone).
    """
    if not (np.isfinite(sigma_min) and np.isfinite(sigma_max) and sigma_min < sigma_max):
        raise ValueError(f"need finite sigma_min < sigma_max; got [{sigma_min}, {sigma_max}]")
    if not (isinstance(grid, int) and grid >= 2):
        raise ValueError(f"grid must be an integer >= 2; got {grid!r}")
    if not 0 < agree_within < 1:
        raise ValueError(f"agree_within must be in (0, 1); got {agree_within!r}")
    started = time.perf_counter()
    check_model(model)
    head = dict(
        eps=params.eps, beta=params.beta, n=params.n, warned=bool(asymptotics_concerns(params, model))
    )
    nan = float("nan")

    def failed(status, sigma_start=nan):
        return TrustPoint(
            **head,
            stable_states=0,
            agree=nan,
            confirmed=nan,
            median_difference=nan,
            max_difference=nan,
            sigma_start=sigma_start,
            branches=0,
            seconds=time.perf_counter() - started,
            status=status,
        )

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)  # recorded in ``warned`` instead
        try:
            paper = frequency_response(params, sigma_min=sigma_min, sigma_max=sigma_max)
            fr = (
                paper
                if model == "slowflow"
                else frequency_response(params, sigma_min=sigma_min, sigma_max=sigma_max, model=model)
            )
            start = slow_flow_start(
                params,
                sigma_min,
                sigma_max,
                segments=shooting.segments,
                response=paper,
                backend=shooting.backend,
            )
        except (ConvergenceError, ValueError) as err:
            return failed(f"no start: {err}")
        for attempt in range(1, START_TRIES + 1):
            try:
                family = trace_orbits(
                    start.params,
                    start.y0,
                    shooting=shooting,
                    branching=branching,
                    interval=ParameterRange(lo=sigma_min, hi=sigma_max),
                )
                break
            except RuntimeError as err:  # ConvergenceError included
                failure = failed(f"orbit continuation failed: {err}", start.sigma)
            if attempt == START_TRIES:
                return failure
            # the next start (an orbit Newton found to 1e-10 can still defeat the continuation's first step)
            try:
                start = slow_flow_start(
                    params,
                    sigma_min,
                    sigma_max,
                    segments=shooting.segments,
                    response=paper,
                    backend=shooting.backend,
                    skip=attempt,
                )
            except (ConvergenceError, ValueError):
                return failure
        sigmas = np.linspace(sigma_min, sigma_max, grid)
        family.branches.extend(
            missed_families(
                params,
                fr,
                family,
                sigmas,
                model=model,
                agree_within=agree_within,
                tries=isola_tries,
                shooting=shooting,
            )
        )
    variant = "paper" if impact is True else impact  # True: (8) as the paper states it
    split = _impact_split(start, sigma_min, sigma_max, variant) if impact else ([], {})
    rows = [
        r for r in compare_rows(family, fr, sigmas, split[0] if impact else None) if r["slow_flow_stable"]
    ]
    if not rows:
        return failed("no stable steady state of (46) in the range", start.sigma)
    d = np.array([r["relative_difference"] for r in rows])
    d_stable = np.array([r["relative_difference_stable_orbit"] for r in rows])
    finite = d[np.isfinite(d)]
    if not finite.size:  # e.g. the orbit found lies on an isola away from every stable state
        return failed(
            f"no traced orbit at the sigma of any of the {len(rows)} stable states of (46)", start.sigma
        )
    return TrustPoint(
        **head,
        stable_states=len(rows),
        agree=float(np.mean(d <= agree_within)),
        confirmed=float(np.mean(d_stable <= agree_within)),  # NaN (no stable orbit) counts as not confirmed
        median_difference=float(np.median(finite)),
        max_difference=float(np.max(finite)),
        sigma_start=start.sigma,
        branches=len(family.branches),
        seconds=time.perf_counter() - started,
        status="ok",
        **(_impact_fields(rows, split[1]) if impact else {}),
    )


IMPACT_SETTLE = 200  # forcing periods of (8) simulated from the family's first orbit


def _impact_split(start, sigma_min, sigma_max, variant):
    """(rows of (8)'s branch, {"impact_status": why not}) from the family's start orbit."""
    try:
        rows = impact_branch_rows(
            start.params,
            np.asarray(start.y0, dtype=float)[:4],
            sigma_min,
            sigma_max,
            settle=IMPACT_SETTLE,
            variant=variant,
        )
    except (RuntimeError, ValueError) as err:  # ConvergenceError included
        return [], {"impact_status": f"no orbit of (8): {' '.join(str(err).split())}"}
    return rows, {}


def _impact_fields(rows, failure: dict) -> dict:
    if failure:
        return failure
    errors = impact_errors(rows)
    measured = errors.pop("measured")
    status = "ok" if measured else "no stable state with a stable orbit of both (8) and (9) nearby"
    return dict(impact_measured=measured, impact_status=status, **errors)


def trust_map(
    base: Params,
    *,
    eps=(0.02, 0.05, 0.1, 0.2),
    beta=(0.0, 0.3, 0.5),
    n=(6, 10, 20, 50),
    sigma_min: float = -6.0,
    sigma_max: float = 8.0,
    workers: Workers = LOCAL,
    resume: Resume | None = None,
    progress=None,
    **options,
) -> list:
    """:func:`trust_point` at every (eps, beta, n) of the grid, the other parameters from ``base``.

    Points run on ``workers`` (by default local processes, one per core; see
    :func:`~slosh_bif.simulation.sweep.run_cells`); ``progress(point, done, total)`` is
    called as they finish. ``options`` go to :func:`trust_point`. Returns the points in grid
    order (eps slowest, n fastest). Interrupted (Ctrl-C, or SIGTERM through the CLI), it kills
    its workers and returns the points done, the others with status ``"not computed: ..."``.
    ``resume``: its ``done``, {grid index: TrustPoint} of an earlier run (not computed again),
    and ``keep(i, point)``, called as each point finishes.
    """
    if not isinstance(base, Params):
        raise TypeError(f"base must be a slosh_bif.Params; got {type(base).__name__}")
    grid = list(itertools.product(eps, beta, n))
    if not grid:
        raise ValueError("the (eps, beta, n) grid is empty")
    jobs = [
        base.replace(eps=float(e), beta=float(b), n=int(k)) for e, b, k in grid
    ]  # Params checks each value
    resume = resume or Resume()
    done = {i: point for i, point in (resume.done or {}).items() if 0 <= i < len(jobs)}
    count = [len(done)]

    def finished(i, point):
        count[0] += 1
        if resume.keep is not None:
            resume.keep(i, point)
        if progress is not None:
            progress(point, count[0], len(jobs))

    one = functools.partial(trust_point, sigma_min=sigma_min, sigma_max=sigma_max, **options)
    results, status = run_cells(
        one, {i: (p,) for i, p in enumerate(jobs)}, workers=workers, resume=Resume(done, finished)
    )
    why = f"not computed: {status}"  # only for the points an interruption left
    return [
        results[i] if i in results else _not_computed(job, why, options.get("model", "slowflow"))
        for i, job in enumerate(jobs)
    ]


def _not_computed(params: Params, why: str, model: str) -> TrustPoint:
    nan = float("nan")
    return TrustPoint(
        eps=params.eps,
        beta=params.beta,
        n=params.n,
        warned=bool(asymptotics_concerns(params, model)),
        stable_states=0,
        agree=nan,
        confirmed=nan,
        median_difference=nan,
        max_difference=nan,
        sigma_start=nan,
        branches=0,
        seconds=0.0,
        status=why,
    )
