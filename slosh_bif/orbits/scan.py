"""Every family of periodic orbits of (9) over a range of sigma (or Abar), each found once.

One start finds the family its orbit lies on: a simulation lands on one attractor, the slow
flow's motion on the resonant branch of (46). :func:`scan_families` gathers starts of every kind
(:func:`~slosh_bif.orbits.scan_starts.scan_starts`: simulations from several states at several values,
every steady state of (46), the impact-free linear response), drops each orbit that lies on a
branch already traced or on its mirror image under the symmetry (X, w, tau) -> (-X, -w, tau + pi)
of (9), and traces each new one with :func:`~slosh_bif.orbits.families.trace_orbits` (switching
included; an isolated family closes on itself). Branch names are unique over the whole scan.

"Lies on a traced branch" is decided by Newton, not by a distance to the branch's polyline
(whose chords are off the curve by up to a step's sagitta): from the traced branch's state
interpolated at the candidate's parameter, Newton there converges to the candidate, or to
its mirror image, when they are the same family.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import ContinuationOptions, ConvergenceError, newton_solve
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import SHOOTING_OPTIONS, trace_new_family
from slosh_bif.orbits.orbit_branch import OrbitBranch, OrbitFamily, images, renamed, unique_name
from slosh_bif.orbits.scan_pool import families_side_by_side, starts_side_by_side
from slosh_bif.orbits.scan_starts import scan_starts, start_jobs
from slosh_bif.orbits.settings import (
    BRANCHING,
    SHOOTING,
    STARTS,
    BranchingSettings,
    ParameterRange,
    ShootingSettings,
    StartSettings,
)
from slosh_bif.orbits.starts import START_TOL
from slosh_bif.report.files import Resume
from slosh_bif.report.tasks import Task, timed

__all__ = ["scan_families", "on_traced_branch"]

_DEGENERATE = 1e-6  # distance of a multiplier from +1 below which the start orbit is not isolated
_NEAR_MAX = 1e-4  # relative distance beyond which two orbits at one parameter value are different orbits


def on_traced_branch(
    params: Params, y0, branches, *, param: str = "sigma", period_multiple: int = 1, tol: float = 1e-6
) -> OrbitBranch | None:
    """The traced branch among ``branches`` (continued in ``param``, orbits of period
    ``period_multiple`` 2pi) that the orbit of (9) through the state ``y0`` at tau = 0 at
    ``params`` lies on, in any of its :func:`~slosh_bif.orbits.orbit_branch.images` (a mirror image,
    a shift by 2pi), else None."""
    p = getattr(params, param)
    for ob in branches:
        problem, b = ob.problem, ob.branch
        if (
            problem.period_multiple != period_multiple
            or b.param != param
            or not _same_except(param, problem.params, params)
        ):
            continue
        crossings = np.flatnonzero((b.p[:-1] - p) * (b.p[1:] - p) <= 0)
        if not crossings.size:
            continue
        x = problem.initial_states(y0, p)
        copies = images(problem, x)
        # Two solutions within the corrector's residual tolerance of each other can lie
        # 1/s_min apart (s_min: smallest singular value of the shooting Jacobian): at beta = 0
        # a multiplier near +1 (the particle barely held between the walls) makes s_min 3e-9
        # and the gap 4e-7. Capped: at a fold s_min vanishes, and distinct branches near a
        # branch point must stay apart.
        s_min = np.linalg.svd(problem.period_jacobian(x, p), compute_uv=False)[
            -1
        ]  # the 2pi problem's: a symmetric orbit's G may be regular where M is not
        near = min(_NEAR_MAX, max(tol, 100 * START_TOL / max(s_min, 1e-300)))
        for i in crossings:
            w = 0.0 if b.p[i + 1] == b.p[i] else (p - b.p[i]) / (b.p[i + 1] - b.p[i])
            run = newton_solve(
                problem,
                (1 - w) * b.x[i] + w * b.x[i + 1],
                p,
                tol=START_TOL,
                max_iter=12,
                criterion="residual",
            )
            if run.converged and any(
                np.linalg.norm(run.x - y) <= near * (1 + np.linalg.norm(y)) for y in copies
            ):
                return ob
    return None


def _covered(ob: OrbitBranch, others, param: str) -> OrbitBranch | None:
    """The branch among ``others`` that holds all of ``ob`` (three points along it, and its
    images), else None."""
    b = ob.branch
    owner = None
    for i in sorted({len(b) // 4, len(b) // 2, (3 * len(b)) // 4}):
        at = ob.problem.params_at(b.p[i])
        found = on_traced_branch(
            at,
            b.x[i, :4],
            [o for o in others if owner is None or o is owner],
            param=param,
            period_multiple=ob.problem.period_multiple,
        )
        if found is None:
            return None
        owner = found
    return owner


def _same_except(param: str, a: Params, b: Params) -> bool:
    return dataclasses.replace(a, **{param: 0.0}) == dataclasses.replace(b, **{param: 0.0})


def scan_families(
    params: Params,
    state0,
    *,
    interval: ParameterRange,
    starts: StartSettings = STARTS,
    shooting: ShootingSettings = SHOOTING,
    branching: BranchingSettings = BRANCHING,
    options: ContinuationOptions | None = None,
    progress=None,
    resume: Resume | None = None,
    executor=None,
) -> OrbitFamily:
    """Every family of 2pi-orbits of (9) (and what branches off them) over ``interval`` (of sigma
    or Abar) that the starts of :func:`~slosh_bif.orbits.scan_starts.scan_starts`
    reach, each traced once.

    ``starts``: where starts are sought; ``shooting``, ``branching`` and ``options`` as for
    :func:`~slosh_bif.orbits.families.trace_orbits` (``branching.max_branches`` bounds the
    branches of each family, the primary one included). Returns one :class:`OrbitFamily` holding
    every branch; each branch's ``found_from`` says which start found it, and its ``tasks`` each
    start job and family traced here, with its duration (not those of a resumed run's skipped
    starts). Raises
    :class:`ConvergenceError` when no start converges. ``resume``: a :class:`Resume` whose
    ``done``, a ``(k, branches)`` of an earlier run with the same settings, skips the first k
    starts (they are found again, in the same order, but not traced), and whose ``keep(k,
    branches)`` is called after the k-th converged start is dealt with (its family traced, or
    found known). ``executor``: a pool (``submit(function, *arguments)`` returning a future, and
    ``threads``, the tasks it runs at once) on which the starts and the families run side by side
    (:mod:`~slosh_bif.orbits.scan_pool`); the result is the sequential one.
    """
    param, p_min, p_max = interval.name, interval.lo, interval.hi
    say = progress or (lambda message: None)
    resume = resume or Resume()
    skip, branches = resume.done if resume.done is not None else (0, [])
    branches = list(branches)
    tracing = dict(
        interval=interval, shooting=shooting, branching=branching, options=options or SHOOTING_OPTIONS
    )
    found = dict(param=param, starts=starts, shooting=shooting)
    tasks = []  # each start job and family traced: its duration (reported, never used)

    def record(start, family, seconds):
        points = sum(len(ob) for ob in family.branches) if family is not None else 0
        tasks.append(Task(len(tasks), "family", start.found_from, seconds, points))

    if executor is None:
        converged = scan_starts(params, state0, p_min, p_max, say=say, tasks=tasks, **found)
    else:
        jobs = start_jobs(params, state0, p_min, p_max, **found)
        converged = starts_side_by_side(jobs, executor, say, tasks)
    tried = 0
    if executor is None:
        for start in converged:
            tried += 1
            if tried <= skip:
                continue
            if not _is_known(start, branches, say, param):
                family, seconds = timed(_trace_here, start, branches, say, tracing, progress)
                record(start, family, seconds)
                _add_family(family, branches, say, param)
            if resume.keep is not None:
                resume.keep(tried, branches)
    else:
        converged = list(converged)
        tried = len(converged)
        families_side_by_side(
            converged,
            branches,
            executor=executor,
            first=skip,
            tracing=tracing,
            take=dict(
                is_known=lambda start: _is_known(start, branches, say, param),
                add=lambda family: _add_family(family, branches, say, param),
                lies_on=lambda start: _is_known(start, branches, lambda message: None, param),
                keep=resume.keep,
                say=say,
                record=lambda k, family, seconds: record(converged[k], family, seconds),
            ),
        )
    if not branches:
        raise ConvergenceError(
            f"no periodic orbit of (9) found from {tried} converged starts in {param} in [{p_min}, {p_max}]"
            if tried
            else f"no start converged to a periodic orbit of (9) in {param} in [{p_min}, {p_max}]"
        )
    return OrbitFamily(params, param, _renamed(branches), tasks=tuple(tasks))


def _is_known(start, branches: list, say, param: str) -> bool:
    """Whether a converged start of the scan gives no new family: its orbit is not isolated, or
    lies on a branch already traced."""
    if np.min(np.abs(start.orbit.multipliers - 1)) < _DEGENERATE:
        # beta = 0 and no wall contact: the particle floats freely, every offset is an orbit
        say(f"scan: the orbit found by {start.found_from} is not isolated (a multiplier at +1): skipped")
        return True
    known = on_traced_branch(start.params, start.y0, branches, param=param)
    if known is not None:
        say(f"scan: the orbit found by {start.found_from} lies on the {known.name} branch")
        return True
    return False


def _trace_here(start, branches: list, say, tracing: dict, progress) -> OrbitFamily | None:
    """The family of a new start, traced in this process beside ``branches``; None when it fails."""
    say(f"scan: a new family from {start.found_from}")
    try:
        return trace_new_family(
            start.params, start.y0, branches, found_from=start.found_from, progress=progress, **tracing
        )
    except ConvergenceError as err:
        say(f"scan: no family traced from {start.found_from}: {err}")
        return None


def _add_family(family: OrbitFamily | None, branches: list, say, param: str) -> None:
    """Add the new branches of ``family`` to ``branches``, each curve once."""
    for new in family.branches if family is not None else ():
        # A closed loop of asymmetric orbits can hold both mirror images, and a family traced
        # from a later start can hold an earlier one's switched piece: keep each curve once.
        holder = _covered(new, branches, param)
        if holder is not None:
            say(f"scan: the {new.name} branch lies on the {holder.name} branch: dropped")
            continue
        for old in [o for o in branches if _covered(o, [new], param) is not None]:
            say(f"scan: the {old.name} branch lies on the new {new.name} branch: replaced")
            branches.remove(old)
        branches.append(new)


def _renamed(branches) -> list:
    """The branches named kind, kind-2, ... in order (dropped duplicates leave gaps in the names
    given while tracing), with the names inside their origins rewritten to match."""
    names = {}
    for ob in branches:
        names[ob.name] = unique_name(
            ob.kind, [dataclasses.replace(o, name=n) for o, n in zip(branches, names.values())]
        )
    return renamed(branches, names)
