"""Start orbits for the families of (9): from a simulation, or from the slow flow's motion.

These are the documented seams of the orbits wing: a start guess from a simulation of (9)
(:mod:`slosh_bif.simulation`) and from the slow flow's leading-order motion (25), (29), (35) on
a steady state of (46) (:mod:`slosh_bif.slowflow`). Everything else in :mod:`slosh_bif.orbits`
knows only the model and the continuation engine.
"""

from __future__ import annotations

import contextlib
import dataclasses
import warnings

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.model.params import Params
from slosh_bif.orbits.orbit_tools import orbit_at, orbit_measures
from slosh_bif.orbits.shooting import PeriodicOrbit, ShootingProblem
from slosh_bif.simulation.direct import SimulationSettings, simulate
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow
from slosh_bif.slowflow.steady_states import forcing_response, frequency_response

# residual tolerance of Newton from a start guess (scan.on_traced_branch resolves orbits to it)
START_TOL = 1e-9

__all__ = [
    "UnsettledStartWarning",
    "UnsettledStartError",
    "StartOrbit",
    "start_orbit",
    "orbit_from_simulation",
    "orbit_from_slow_flow",
    "slow_flow_start",
    "guess_only",
    "stable_steady_states",
    "slow_flow_motion",
    "settle_and_shoot",
]


# A strobe that still moves by this much (relative) in the last period is not near a fixed point:
# the Fig. 13 preset's run moves by 0.1-0.2 at period 150 (it is captured near period 160), and
# which orbit Newton reached from it changed with the last bits of the compiled loop.
UNSETTLED = 1e-2
REACHED = 0.05  # a strobe this close (relative) to the stable orbit Newton finds from it has reached it


class UnsettledStartError(ConvergenceError):
    """The simulation meant to reach a start orbit has not settled (see :func:`orbit_from_simulation`)."""


class UnsettledStartWarning(UserWarning):
    """The simulation a start orbit is taken from had not settled on a periodic state."""


@dataclasses.dataclass(frozen=True)
class StartOrbit:
    """A converged 2pi-orbit of (9) to start a family from.

    ``params`` is the parameter set *at the orbit* (a start from the slow flow moves sigma to the
    steady state it used), so ``trace_orbits(start.params, start.y0, ...)`` is always right;
    ``orbit`` the :class:`PeriodicOrbit`; ``found_from`` how it was found.
    """

    params: Params
    orbit: PeriodicOrbit
    found_from: str

    @property
    def y0(self):
        return self.orbit.y0

    @property
    def sigma(self) -> float:
        return self.params.sigma


def orbit_from_simulation(
    params: Params,
    state0,
    *,
    settle: int = 150,
    guess=None,
    segments: int = 4,
    tries: int = 50,
    backend: str = "auto",
    unsettled: str = "warn",
) -> StartOrbit:
    """A converged 2pi-orbit near ``guess``, or near the strobe states (tau = 2 pi k) of a
    simulation of (9) from ``state0`` over ``settle`` periods: the last strobe first, then up to
    ``tries - 1`` before it. Raises :class:`ConvergenceError` naming what was tried. A simulation
    that has not settled gives an :class:`UnsettledStartWarning` (``unsettled="warn"``) or
    raises :class:`UnsettledStartError` (``"raise"``)."""
    if not (isinstance(settle, int) and settle >= 0):
        raise ValueError(f"settle must be an integer >= 0 (forcing periods); got {settle!r}")
    if unsettled not in ("warn", "raise"):
        raise ValueError(f"unsettled must be 'warn' or 'raise'; got {unsettled!r}")
    problem = ShootingProblem(params, segments=segments, backend=backend)
    if guess is not None:
        guesses = [np.asarray(guess, dtype=float)]
        if guesses[0].shape != (4,) or not np.all(np.isfinite(guesses[0])):
            raise ValueError(f"guess must be 4 finite numbers [X, X', w, w']; got {guess!r}")
    else:
        strobes = integrate_grid(params, state0, 2 * np.pi * np.arange(settle + 1), backend=backend)
        guesses = list(strobes[::-1][:tries])
        moved = float(np.linalg.norm(strobes[-1] - strobes[-2])) if settle >= 1 else 0.0
        if moved > UNSETTLED * (1 + np.linalg.norm(strobes[-1])):  # still moving each period, not converging
            # A run that has not settled amplifies rounding: which orbit Newton finds from its
            # strobes depends on the integrator (the Fig. 10 set: the compiled path lands on the
            # symmetric orbit, scipy's on an asymmetric one).
            why = (
                f"the {settle}-period simulation from the initial state has not settled (its strobe "
                f"moved by {moved:.2g} in the last period)"
            )
            if unsettled == "raise":
                raise UnsettledStartError(why)
            warnings.warn(
                f"{why}: the start orbit found from it depends on the integrator's rounding; "
                "--start scan (scan_families) finds every family",
                UnsettledStartWarning,
                stacklevel=2,
            )
    for k, y0 in enumerate(guesses):
        orbit = orbit_at(problem, problem.initial_states(y0), params.sigma, tol=START_TOL)
        if orbit.converged:
            where = (
                "the guess"
                if guess is not None
                else f"the strobe state of period {settle - k} of a simulation"
            )
            return StartOrbit(params, orbit, f"Newton from {where}")
    where = (
        "the guess"
        if guess is not None
        else f"the last {len(guesses)} strobe states of a {settle}-period simulation"
    )
    raise ConvergenceError(f"no periodic orbit found near {where} at sigma = {params.sigma:g}")


def start_orbit(
    params: Params,
    state0,
    p_range: tuple | None = None,
    *,
    settle: int = 150,
    guess=None,
    segments: int = 4,
    backend: str = "auto",
    param: str = "sigma",
) -> StartOrbit:
    """The default start of a family: the stable orbit a ``settle``-period simulation has reached.

    "Reached": Newton from the last strobe state converges to a stable orbit within ``REACHED``
    (relative) of that state, so that the run is in the orbit's basin, close to it, and the last
    bits of the integration (which differ between machines: glibc picks its ``cos``/``pow`` by
    the CPU) cannot send Newton elsewhere. Otherwise (a strongly modulated run, an unstable or no
    orbit near its strobe) the slow flow's start over ``p_range`` (lo, hi) of ``param`` (sigma,
    or Abar at the set's sigma), which no rounding moves: from an unsettled Fig. 10 run Newton
    found the symmetric orbit on one build and an asymmetric one on another. Without a range,
    with a ``guess``, or when the slow flow's start fails too, :func:`orbit_from_simulation` as
    it is (with its warning when the run has not settled). Where the set's ``param`` lies outside
    ``p_range``, the slow flow's start alone (no simulation: its orbit would lie outside)."""
    if p_range is None or guess is not None:
        return orbit_from_simulation(
            params, state0, settle=settle, guess=guess, segments=segments, backend=backend
        )
    if not (isinstance(settle, int) and settle >= 1):
        raise ValueError(f"settle must be an integer >= 1 (forcing periods); got {settle!r}")
    p0, (lo, hi) = getattr(params, param), p_range
    if not lo <= p0 <= hi:  # the simulation's orbit could not start a family over the range
        start = slow_flow_start(params, lo, hi, segments=segments, backend=backend, param=param)
        return dataclasses.replace(
            start, found_from=f"{start.found_from} (the set's {param} = {p0:g} lies outside [{lo:g}, {hi:g}])"
        )
    strobe = integrate_grid(params, state0, [0.0, 2 * np.pi * settle], backend=backend)[-1]
    problem = ShootingProblem(params, segments=segments, backend=backend)
    orbit = orbit_at(problem, problem.initial_states(strobe), params.sigma, tol=START_TOL)
    distance = float(np.linalg.norm(strobe - orbit.y0)) if orbit.converged else np.inf
    if orbit.converged and orbit.stable and distance <= REACHED * (1 + np.linalg.norm(orbit.y0)):
        return StartOrbit(
            params,
            orbit,
            f"Newton from the strobe state of period {settle} of a simulation, {distance:.2g} from "
            "this stable orbit",
        )
    why = (
        "Newton from its last strobe found no orbit"
        if not orbit.converged
        else f"its last strobe is {distance:.2g} from the {'stable' if orbit.stable else 'unstable'} "
        "orbit Newton finds from it"
    )
    try:
        start = slow_flow_start(params, *p_range, segments=segments, backend=backend, param=param)
    except (ConvergenceError, ValueError):  # no orbit from (46)'s states, or (46) has none
        return orbit_from_simulation(params, state0, settle=settle, segments=segments, backend=backend)
    return dataclasses.replace(
        start,
        found_from=f"{start.found_from} (the {settle}-period simulation has not reached a stable orbit: "
        f"{why})",
    )


def orbit_from_slow_flow(
    params: Params,
    A: float,
    *,
    psi: float | None = None,
    segments: int = 4,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    tol: float = 1e-10,
    backend: str = "auto",
    model: str = "slowflow",
):
    """Newton on (9) from the slow flow's motion at amplitude A (a steady state of (46) at
    ``params``, or of the corrected slow flow with ``model="corrected"``; its phase ``psi`` when
    known, else from (46)): each arc starts on :meth:`SlowFlow.fast_state` at its own start time,
    so that multiple shooting does not carry the guess's error across the period. Returns a
    :class:`PeriodicOrbit` (``converged`` says whether Newton found one)."""
    with guess_only():
        flow = SlowFlow(params, model)
    psi = float(flow.steady_phase(A)) if psi is None else float(psi)
    problem = ShootingProblem(params, segments=segments, rtol=rtol, atol=atol, backend=backend)
    x = flow.fast_state(A, psi, problem.arc_times()[:-1]).ravel()
    return orbit_at(problem, x, params.sigma, tol=tol)


def stable_steady_states(
    params: Params, lo: float, hi: float, *, tries: int = 12, response=None, param: str = "sigma"
) -> list:
    """Up to ``tries`` stable steady states of (46) with ``param`` (sigma or Abar) in [lo, hi], as
    (params at their value, A, psi): the start guesses of the orbits of (9)
    (:func:`slow_flow_start`) and of (8) (:func:`slosh_bif.orbits.impact.starts.impact_start`).
    From the ends of the range inward, where the slow flow is closest to the full models, spread
    over the branch's points (neighbours are nearly the same guess). ``response``: (46)'s steady
    states over the range, if already traced."""
    if param not in ("sigma", "Abar"):
        raise ValueError(f"the slow flow's steady states are continued in sigma or Abar; got {param!r}")
    fr = response
    if fr is None:
        with guess_only():
            fr = (
                frequency_response(params, sigma_min=lo, sigma_max=hi)
                if param == "sigma"
                else forcing_response(params, abar_min=lo, abar_max=hi)
            )
    # (value, A, psi): the branch's own phase (at a branch's end on A_min, (46)'s phase balance is
    # a square root of rounding, NaN: seen at n = 6, eps = 0.02)
    candidates = [
        (float(b.p[i]), float(b.x[i, 0]), float(b.x[i, 1]))
        for b in fr.branches
        for i in range(len(b))
        if b.stable[i] and lo <= b.p[i] <= hi
    ]
    candidates.sort(key=lambda c: min(c[0] - lo, hi - c[0]))
    picks = candidates[:: max(1, len(candidates) // tries)][:tries]
    return [(params.replace(**{param: value}), A, psi) for value, A, psi in picks]


def slow_flow_motion(params: Params, A: float, psi: float, tau) -> np.ndarray:
    """The slow flow's leading-order motion [X, X', w, w'] at the fast times ``tau`` on its state
    (A, psi) (:meth:`SlowFlow.fast_state`, eqs. 25, 29, 35): a start guess for either model."""
    with guess_only():
        return SlowFlow(params).fast_state(A, psi, np.asarray(tau, dtype=float))


@contextlib.contextmanager
def guess_only():
    """The slow flow as a start guess for Newton on a full model: its checked range is no concern
    there (the orbit found does not depend on the guess's accuracy), so it does not warn."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        yield


def slow_flow_start(
    params: Params,
    lo: float,
    hi: float,
    *,
    segments: int = 4,
    tries: int = 12,
    response=None,
    backend: str = "auto",
    skip: int = 0,
    param: str = "sigma",
) -> StartOrbit:
    """A :class:`StartOrbit`: a 2pi-orbit of (9) found from a stable steady state of (46) with
    ``param`` (sigma, or Abar at the set's sigma) in [lo, hi], for starting :func:`trace_orbits`
    without a simulation; its ``params`` carry the value of that steady state.

    States are tried from the ends of the range inward: far from the peak the slow flow is
    closest to (9) (Fig. 10 set: 8 of 16 evenly spread stable states converge, all with
    |sigma| >= 0.5; at the peak, where (46) and (9) differ by 30 %, none). Raises
    :class:`ConvergenceError` naming how many were tried. ``response``: the frequency response of
    (46) over the range, if already traced. ``skip``: pass over the first ``skip`` orbits found
    (a caller whose continuation failed from the first asks for the next).
    """
    picks = stable_steady_states(params, lo, hi, tries=tries, response=response, param=param)
    for at, A, psi in picks:
        orbit = orbit_from_slow_flow(at, A, psi=psi, segments=segments, backend=backend)
        if orbit.converged:
            if skip == 0:
                return StartOrbit(
                    at,
                    orbit,
                    f"Newton from the slow flow's motion on the stable steady state A = {A:.6g} of (46)",
                )
            skip -= 1
    raise ConvergenceError(
        f"no orbit of (9) found from {len(picks)} stable steady states of (46) in {param} in [{lo}, {hi}]"
        if picks
        else f"(46) has no stable steady state in {param} in [{lo}, {hi}] to start (9) from"
    )


def settle_and_shoot(
    params: Params,
    state0,
    rtol: float = 1e-10,
    *,
    segments: int = 4,
    sim_rtol: float = 1e-8,
    first: int = 200,
    every: int = 100,
    most: int = 1000,
):
    """(orbit, A1): a stable 2pi-orbit of (9) reached from ``state0``, and its first-harmonic amplitude.

    Simulates (9) and, after ``first`` forcing periods and then every ``every`` periods up to
    ``most``, tries Newton (arcs integrated at ``rtol``) from the current state; the first stable
    orbit wins. ``first=0`` tries the start itself first. Capture can take long and its time
    depends on rounding (the Fig. 13 set: transient chaos; 300 periods at rtol 1e-7 were not
    enough where 1e-6 and 1e-9 were), so one fixed settling time is not enough. A1 is NaN, and
    the orbit the last attempt's, when no stable orbit was found.
    """
    y = np.asarray(state0, dtype=float)
    if y.shape != (4,) or not np.all(np.isfinite(y)):
        raise ValueError(f"state0 must be 4 finite numbers [X, X', w, w']; got {state0!r}")
    if not (isinstance(every, int) and every >= 1 and isinstance(first, int) and 0 <= first <= most):
        raise ValueError(
            f"need integers every >= 1 and 0 <= first <= most; got every={every!r}, "
            f"first={first!r}, most={most!r}"
        )
    tau, orbit = 0.0, None
    for periods in range(first, most + 1, every):
        if periods > 0:
            sim = simulate(
                params,
                y,
                periods * 2 * np.pi,
                t0=tau,
                settings=SimulationSettings(rtol=sim_rtol, atol=sim_rtol * 1e-2, sample_step=0.1),
            )
            if not sim.success:
                raise RuntimeError(f"settling simulation failed: {sim.message}")
            y, tau = sim.y[:, -1], periods * 2 * np.pi
        problem = ShootingProblem(params, segments=segments, rtol=rtol, atol=rtol * 1e-2)
        orbit = orbit_at(problem, problem.initial_states(y), params.sigma, tol=max(1e-11, 100 * rtol))
        if orbit.converged and orbit.stable:
            return orbit, orbit_measures(problem, problem.initial_states(orbit.y0), params.sigma)["A1"]
    return orbit, np.nan
