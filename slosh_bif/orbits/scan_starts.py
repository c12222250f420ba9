"""Where a scan for every family of 2pi-orbits looks: the stable steady states of the slow flow (46)
over the range, the linear response, and seeded random states in a box, each settled by
simulating (9) and refined by shooting."""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.model.equations import SmoothModel
from slosh_bif.model.params import Params
from slosh_bif.orbits.orbit_tools import orbit_at
from slosh_bif.orbits.settings import SHOOTING, STARTS, ShootingSettings, StartSettings
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import START_TOL, StartOrbit, guess_only, orbit_from_slow_flow
from slosh_bif.report.tasks import Task, timed
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.slowflow.steady_states import forcing_response, frequency_response

__all__ = [
    "linear_response_state",
    "scan_starts",
    "start_jobs",
]


def linear_response_state(params: Params) -> np.ndarray:
    """The state at tau = 0 of the impact-free 2pi-response of the linear part of (9), Re Y with
    Y = (i - J)^-1 F: the non-resonant response of Fig. 11 while |w| stays well inside the walls
    (where chi w^(2n+1) is negligible)."""
    smooth = SmoothModel(params)
    zero = np.zeros(4)
    return np.linalg.solve(1j * np.eye(4) - smooth.jac(0.0, zero), smooth.rhs(0.0, zero).astype(complex)).real


def _steady_states_near(params: Params, param: str, values, p_min, p_max):
    """(v, p, A, stable) of every branch of (46) in ``param`` where it crosses each v of ``values``
    (the branch's own point: Newton on (9) then sits exactly at that point's p)."""
    try:
        with guess_only():
            if param == "sigma":
                fr = frequency_response(params, sigma_min=p_min, sigma_max=p_max)
            else:
                fr = forcing_response(params, abar_min=max(p_min, 0.0), abar_max=p_max)
    except (ValueError, RuntimeError, ConvergenceError):
        return []  # no slow manifold or no steady state: the other starts remain
    found = []
    for b in fr.branches:
        for v in values:
            for i in np.flatnonzero((b.p[:-1] - v) * (b.p[1:] - v) <= 0):
                j = i if abs(b.p[i] - v) <= abs(b.p[i + 1] - v) else i + 1
                found.append((v, float(b.p[j]), float(b.x[j, 0]), bool(b.stable[j])))
    return found


_RANDOM_BOX = np.array(
    [3.0, 3.0, 1.0, 3.0]
)  # |X|, |X'|, |w|, |w'| of the random starts: the walls and beyond Fig. 10's speeds


def scan_starts(
    params: Params,
    state0,
    p_min: float,
    p_max: float,
    *,
    param: str = "sigma",
    starts: StartSettings = STARTS,
    shooting: ShootingSettings = SHOOTING,
    say=None,
    tasks: list | None = None,
):
    """Converged 2pi-orbits of (9) from many starts over [p_min, p_max] of ``param`` (sigma or
    Abar), one :class:`StartOrbit` per start that converges (duplicates included: the caller
    keeps the new). ``tasks``: a list that gets one :class:`~slosh_bif.report.tasks.Task` per job
    of :func:`start_jobs` (its duration and the orbits it converged to).

    With ``starts`` (:class:`StartSettings`), at ``starts.points`` evenly spread values of the
    parameter: Newton from the impact-free linear response, and from the last strobe state of a
    ``starts.settle``-period simulation from ``state0``, from rest, from the slow flow's motion on
    each steady state of (46) there and from ``starts.random_starts`` states drawn uniformly from
    |X|, |X'|, |w'| <= 3, |w| <= 1 (numpy's generator seeded with ``starts.seed``); then Newton from the slow
    flow's motion itself on every
    steady state of (46) (stable and unstable, each at its own parameter value).
    """
    say = say or (lambda message: None)
    jobs = start_jobs(params, state0, p_min, p_max, param=param, starts=starts, shooting=shooting)
    for function, arguments, label in jobs:
        (found, messages), seconds = timed(function, *arguments)
        if tasks is not None:
            tasks.append(Task(len(tasks), "start", label, seconds, len(found)))
        for message in messages:
            say(message)
        yield from found


def start_jobs(
    params: Params,
    state0,
    p_min: float,
    p_max: float,
    *,
    param: str = "sigma",
    starts: StartSettings = STARTS,
    shooting: ShootingSettings = SHOOTING,
) -> list:
    """The starts of :func:`scan_starts` as independent jobs ``(function, arguments, label)``, in
    its order: ``function(*arguments)`` gives (the converged :class:`StartOrbit` list, the progress
    messages); ``label`` says where the job looks. One job per value of the parameter (its
    simulations and Newton runs), one per steady state of (46); the random states are drawn here,
    in the sequential order."""
    if param not in ("sigma", "Abar"):
        raise ValueError(f"param must be 'sigma' or 'Abar'; got {param!r}")
    rng = np.random.default_rng(starts.seed)
    grid = np.linspace(p_min, p_max, starts.points + 2)[1:-1]
    states = _steady_states_near(params, param, grid, p_min, p_max)
    jobs = []
    for v in grid:
        at = params.replace(**{param: float(v)})
        initial = [(np.asarray(state0, dtype=float), "the preset's initial state"), (np.zeros(4), "rest")]
        if at.Abar > 0:
            with guess_only():
                flow = SlowFlow(at)
            initial += [
                (flow.fast_state(A, float(flow.steady_phase(A)), 0.0), f"the slow flow's state A = {A:.4g}")
                for at_v, _, A, _ in states
                if at_v == v and A > flow.A_min
            ]
        initial += [
            (rng.uniform(-_RANDOM_BOX, _RANDOM_BOX), f"random state {k + 1} (seed {starts.seed})")
            for k in range(starts.random_starts)
        ]
        label = f"the starts at {param} = {v:.6g}"
        jobs.append((_starts_at, (at, param, float(v), initial, starts.settle, shooting), label))
    for _, value, A, stable in states:
        at = params.replace(**{param: value})
        with guess_only():
            A_min = SlowFlow(at).A_min
        if A > A_min:  # a state on the end of S+: (46)'s phase there is a root of rounding
            label = f"the slow flow's motion on A = {A:.6g} at {param} = {value:.6g}"
            jobs.append((_start_from_slow_flow, (at, param, value, A, stable, shooting), label))
    return jobs


def _starts_at(at: Params, param: str, v: float, initial, settle: int, shooting: ShootingSettings):
    """The converged orbits at one value ``v`` of ``param``: Newton from the linear response and
    from the end of a ``settle``-period simulation from each ``(state, what)`` of ``initial``."""
    messages = []
    problem = ShootingProblem(
        at, segments=shooting.segments, rtol=shooting.rtol, atol=shooting.atol, backend=shooting.backend
    )
    guesses = [(linear_response_state(at), "the impact-free linear response")]
    for y, what in initial:
        try:
            guesses.append(
                (
                    integrate_grid(at, y, [0.0, 2 * np.pi * settle], backend=shooting.backend)[-1],
                    f"a {settle}-period simulation from {what}",
                )
            )
        except RuntimeError as err:
            messages.append(f"scan: simulation from {what} at {param} = {v:.4g} failed ({err})")
    found = []
    for y, what in guesses:
        messages.append(f"scan: Newton at {param} = {v:.4g} from {what}")
        try:  # the arcs' start states: one period of (9) from the guess
            x = problem.initial_states(y)
        except RuntimeError as err:  # a state deep in the wall, say: the other guesses remain
            messages.append(f"scan: no arcs from {what} at {param} = {v:.4g} ({err})")
            continue
        orbit = orbit_at(problem, x, at.sigma, tol=START_TOL)
        if orbit.converged:
            found.append(StartOrbit(at, orbit, f"Newton at {param} = {v:.6g} from {what}"))
    return found, messages


def _start_from_slow_flow(at: Params, param: str, value: float, A: float, stable: bool, shooting):
    """The orbit from the slow flow's motion on the steady state A of (46) at ``value``."""
    messages = [f"scan: Newton at {param} = {value:.4g} from the slow flow's motion on A = {A:.4g}"]
    orbit = orbit_from_slow_flow(
        at, A, segments=shooting.segments, rtol=shooting.rtol, atol=shooting.atol, backend=shooting.backend
    )
    if not orbit.converged:
        return [], messages
    found_from = (
        f"Newton from the slow flow's motion on the {'stable' if stable else 'unstable'} "
        f"steady state A = {A:.6g} of (46) at {param} = {value:.6g}"
    )
    return [StartOrbit(at, orbit, found_from)], messages
