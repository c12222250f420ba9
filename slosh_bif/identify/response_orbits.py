"""The full model's side of a frequency-response fit: the stable 2pi-orbits of (9) at the data's
detunings and the amplitude A1 of their first harmonic (the A of eq. 25 that the slow flow
approximates), followed from one parameter set to the next.

At the first parameter set the family of 2pi-orbits is traced over the data's sigma range from a
start on the slow flow (:func:`~slosh_bif.orbits.families.trace_orbits`, with switching at its
pitchforks and period doublings); the orbits found at each point's sigma (interpolated between the
branch's points, corrected by Newton at the point's own sigma) are its candidates, and the point
takes the stable one that explains it best (:func:`~.assignment.pick`: a sweep's continuing orbit
where that explains it nearly as well). Where none of
those is stable, and for data in Hz (each point its own gamma and Abar, so no one family), the
orbits Newton finds from the slow flow's motion on each steady state of (46) at the point's own set
are tried too, and where still none is stable the orbit a simulation of (9) settles on from those
states or from rest. At any later parameter set each orbit is Newton's from the last one (through
intermediate sets where Newton from the last misses; the least squares moves the parameters by small
steps), stable or not (a fit started off the truth may pass parameter sets where the measured orbit
is unstable); :attr:`OrbitResponse.stable` says which are stable at the last set, and an orbit
Newton loses is reported, never replaced silently by another.
"""

from __future__ import annotations

import warnings

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.identify.assignment import pick
from slosh_bif.identify.response_model import impact_free, impact_free_state, response_curve
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.harmonic_sensitivity import first_harmonic_gradient
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import orbit_from_slow_flow, settle_and_shoot, slow_flow_start
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow

__all__ = ["OrbitResponse", "LostOrbit", "intermediate_sets"]

SEGMENTS = 4  # arcs of each orbit's shooting problem
NEUTRAL = 1e-8  # a multiplier this far outside the unit circle is on it (rounding)
FREE_W = 0.9  # an orbit whose |w| stays below this does not touch the wall (chi w^(2n+1) ~ 0)
SETTLE = 100  # forcing periods a settling simulation runs before each Newton
SETTLE_MOST = 2000  # forcing periods a settled record's simulation from rest runs at most
SETTLED = 1e-7  # the state a period apart agrees this well (relative) when it has settled
SUBSTEPS = 8  # parameter sets between the last and the next where Newton from the last misses


class LostOrbit(ValueError):
    """No orbit to follow at a data point, or Newton lost the one it followed."""


class OrbitResponse:
    """A1 of the stable 2pi-orbit of (9) that each point of ``data`` follows, at any parameter set
    near the first (:meth:`amplitudes`); ``family``: (9)'s orbits already traced near ``params``
    over the data's sigma range, for the guesses (traced here when None and the data share one set)."""

    def __init__(self, data, params: Params, progress=None, family=None):
        say = progress or (lambda message: None)
        self.sigma = np.asarray(data.sigma, dtype=float)
        self.data, self.params = data, params
        if family is None and data.ratio is None:  # one set: its family, traced once, gives the guesses
            lo, hi = float(self.sigma.min()), float(self.sigma.max())
            pad = 0.05 * (hi - lo) + 0.05
            say(f"orbits of (9): the family over sigma in [{lo - pad:.4g}, {hi + pad:.4g}]")
            try:
                start = slow_flow_start(params, lo - pad, hi + pad, segments=SEGMENTS)
                family = trace_orbits(
                    start.params, start.y0, interval=ParameterRange(name="sigma", lo=lo - pad, hi=hi + pad)
                )
            except ConvergenceError as err:  # no start on the slow flow: each point's own search
                say(f"orbits of (9): no family traced ({err}); each point searched on its own")
        elif family is None:
            say(f"orbits of (9): from the slow flow's steady states at each of {len(self.sigma)} points")
        self.family = family  # (9)'s orbits over the data's sigma range at ``params``, or None
        self.x, self.stable = [None] * len(data), [None] * len(data)
        self.candidates = [None] * len(data)  # (A1, stable) of every orbit found at each point
        self.found = [None] * len(data)  # (x, A1, stable) of every orbit found at each point
        chosen = np.empty(len(data))
        problems = self._problems(params)
        for i, previous in data.sweep_order():
            problem, s = problems[i], self.sigma[i]
            guesses = [y0 for _, y0 in _near(family, s)] if family is not None else []
            at = data.params_at(params, i)
            if impact_free(at)[1] < 1.0:  # the non-resonant response: the linear flight's, nearly
                guesses.append(impact_free_state(at))
            found = [_orbit(problem, problem.initial_states(y0, s), s) for y0 in guesses]
            found = [f for f in found if f is not None]
            if family is None or not any(f[2] for f in found):  # each state of (46) at the point's set
                found += [
                    _orbit(problem, problem.initial_states(y0, s), s)
                    for y0 in _slow_flow_guesses(data, params, i)
                ]
                found = [f for f in found if f is not None]
            if not any(f[2] for f in found):  # none stable: where a simulation of (9) settles
                found += _settled(data, params, i, problem)
            if not found:
                raise LostOrbit(f"no 2pi-orbit of (9) found at sigma = {s:.6g} to follow")
            self.candidates[i], self.found[i] = _distinct([(f[1], f[2]) for f in found]), found
            # the stable orbit that explains the point best, its sweep's continuing one where that
            # explains it nearly as well
            k = pick(data, i, None if previous is None else chosen[previous], [(f[1], f[2]) for f in found])
            self.x[i], self.stable[i], chosen[i] = found[k][0], found[k][2], found[k][1]

    def amplitudes(self, params: Params) -> np.ndarray:
        """A1 at each point's sigma for ``params``; :class:`LostOrbit` where an orbit is lost. The
        orbits found become the next call's starts."""
        found = [_orbit(problem, x, s) for problem, x, s in zip(self._problems(params), self.x, self.sigma)]
        for i in [i for i, f in enumerate(found) if f is None]:
            found[i] = self._followed(i, params)
        lost = [s for f, s in zip(found, self.sigma) if f is None]
        if lost:
            raise LostOrbit(
                f"the orbits of (9) at sigma = {', '.join(f'{s:.4g}' for s in lost)} are lost at {params}"
            )
        self.x, self.stable = [f[0] for f in found], [f[2] for f in found]
        self.params = params
        return np.array([f[1] for f in found])

    def gradient(self, names) -> np.ndarray:
        """dA1/d(``names``) at each point, shape (points, len(names)), at the parameter set of the
        last :meth:`amplitudes` call, the orbits moving with the parameters: from the variational
        equations of (9) (:func:`~slosh_bif.orbits.harmonic_sensitivity.first_harmonic_gradient`),
        not from differences of orbits."""
        rows = []
        for i, x in enumerate(self.x):
            directions = [self.data.direction_at(i, name) for name in names]
            rows.append(first_harmonic_gradient(self.data.params_at(self.params, i), x[:4], directions)[1])
        return np.array(rows)

    def state(self):
        """What the next call starts from (the orbits and the set they are at), for :meth:`restore`."""
        return list(self.x), list(self.stable), self.params

    def restore(self, state) -> None:
        self.x, self.stable, self.params = list(state[0]), list(state[1]), state[2]

    def _followed(self, i: int, params: Params):
        """Point i's orbit at ``params`` followed from the last set's through SUBSTEPS sets in
        between (the parameters that differ moved linearly), or None."""
        x = self.x[i]
        for at in intermediate_sets(self.params, params):
            problem = self._problems(at, only=i)
            found = _orbit(problem, x, self.sigma[i])
            if found is None:
                return None
            x = found[0]
        return found

    def settled_from_rest(self, i: int) -> list:
        """[(x, A1, stable)] of the orbit a simulation of (9) from rest settles on at point i's set
        (the one the last call left): Newton only once the state a period apart agrees to
        :data:`SETTLED` (a state near one stable orbit can lie in the basin of another, and Newton
        from it find the first), or [] where it settles on no stable orbit within
        :data:`SETTLE_MOST` periods."""
        at, s = self.data.params_at(self.params, i), float(self.sigma[i])
        y = np.zeros(4)
        period = 2 * np.pi
        for _ in range(SETTLE_MOST // SETTLE):
            try:
                ends = integrate_grid(
                    at, y, np.array([0.0, (SETTLE - 1) * period, SETTLE * period]), rtol=1e-10, atol=1e-12
                )
            except (RuntimeError, ValueError):  # an integration that fails: no orbit from rest
                return []
            y = ends[-1]
            if not np.all(np.isfinite(y)):
                return []
            if np.max(np.abs(ends[-1] - ends[-2])) <= SETTLED * (1.0 + np.max(np.abs(y))):
                problem = self._problems(self.params, only=i)
                found = _orbit(problem, problem.initial_states(y), s)
                return [found] if found is not None and found[2] else []
        return []

    def mirrored(self, i: int, orbit) -> tuple | None:
        """(x, A1, stable) of the mirror twin y(tau + pi) -> -y of ``orbit`` (an (x, A1, stable) at
        point i's set, the one the last call left): the same first harmonic, another motion where
        the orbit is asymmetric; None where Newton does not converge from it."""
        at, s = self.data.params_at(self.params, i), float(self.sigma[i])
        half = integrate_grid(at, orbit[0][:4], np.array([0.0, np.pi]), rtol=1e-12, atol=1e-13)[-1]
        problem = self._problems(self.params, only=i)
        return _orbit(problem, problem.initial_states(-half), s)

    def _problems(self, params: Params, only: int | None = None):
        """Each point's shooting problem: one for all but data in Hz, whose points each have their
        own gamma and Abar (``only``: point only's problem)."""
        if only is not None:
            return ShootingProblem(self.data.params_at(params, only), segments=SEGMENTS)
        if self.data.ratio is None:
            return [ShootingProblem(params, segments=SEGMENTS)] * len(self.sigma)
        return [
            ShootingProblem(self.data.params_at(params, i), segments=SEGMENTS) for i in range(len(self.sigma))
        ]


def intermediate_sets(last: Params, params: Params, count: int = SUBSTEPS) -> list:
    """``count`` parameter sets from ``last`` (excluded) to ``params`` (included), the real
    parameters that differ moved linearly: the steps an orbit is followed through where Newton
    from the last set misses."""
    a, b = last.as_dict(), params.as_dict()
    moved = {k: v for k, v in b.items() if v != a[k] and k not in ("n", "pbar")}
    return [
        params.replace(**{k: a[k] + w * (v - a[k]) for k, v in moved.items()})
        for w in np.linspace(0.0, 1.0, count + 1)[1:]
    ]


def _orbit(problem: ShootingProblem, x, sigma):
    """(x, A1, stable) of the orbit Newton finds from x at sigma, or None."""
    run = newton_solve(problem, x, sigma, tol=1e-10, max_iter=20, criterion="residual")
    if not run.converged:
        return None
    mu = problem.eigenvalues(run.x, sigma)
    measures = orbit_measures(problem, run.x, sigma)
    # far from the walls the particle's relative mode is undamped in (9) too: multipliers on the
    # unit circle, a neutrally stable orbit that a sweep can stay on
    free = measures["max_abs_w"] < FREE_W
    stable = bool(problem.is_stable(mu)) or (free and float(np.max(np.abs(mu))) <= 1.0 + NEUTRAL)
    return run.x, measures["A1"], stable


def _distinct(candidates, tol=1e-7) -> list:
    """The (A1, stable) candidates with the orbits that several guesses reached listed once."""
    out = []
    for A1, stable in sorted(candidates):
        if not out or abs(A1 - out[-1][0]) > tol * max(1.0, abs(A1)) or stable != out[-1][1]:
            out.append((float(A1), bool(stable)))
    return out


def _slow_flow_guesses(data, params: Params, i: int) -> list:
    """States at tau = 0 of the orbits of (9) that Newton finds from the slow flow's motion on each
    steady state of (46) at point i's own parameter set (the nearest its amplitude first)."""
    at = data.params_at(params, i)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        states = sorted(response_curve(at).states_at(at.sigma), key=lambda st: abs(st[0] - data.A[i]))
        orbits = [orbit_from_slow_flow(at, A, segments=SEGMENTS) for A, _ in states]
    return [orbit.y0 for orbit in orbits if orbit.converged]


def _settled(data, params: Params, i: int, problem: ShootingProblem) -> list:
    """(x, A1, stable) of the stable orbit a simulation of (9) settles on (Newton tried after
    SETTLE periods and every SETTLE more, up to four times) from the slow flow's motion on each
    steady state of (46) at point i's set, the nearest its amplitude first, and from rest; the
    first found, or nothing."""
    at, s = data.params_at(params, i), float(data.sigma[i])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        states = sorted(response_curve(at).states_at(at.sigma), key=lambda st: abs(st[0] - data.A[i]))
        flow = SlowFlow(at)
        starts = [flow.fast_state(A, float(flow.steady_phase(A)), np.array([0.0]))[0] for A, _ in states]
    for y0 in starts + [np.zeros(4)]:
        found = _settle_from(at, y0, problem, s)
        if found:
            return found
    return []


def _settle_from(at: Params, y0, problem: ShootingProblem, s: float) -> list:
    """[(x, A1, stable)] of the stable orbit a simulation of (9) at ``at`` settles on from ``y0``
    (Newton tried after SETTLE periods and every SETTLE more, up to four times), or []."""
    try:
        orbit, A1 = settle_and_shoot(at, y0, segments=SEGMENTS, first=SETTLE, every=SETTLE, most=4 * SETTLE)
    except (RuntimeError, ValueError):  # a simulation that fails, a start off the manifold
        return []
    found = _orbit(problem, problem.initial_states(orbit.y0), s) if np.isfinite(A1) else None
    return [found] if found is not None and found[2] else []


def _near(family, sigma) -> list:
    """(A1, y0) guesses of each 2pi-orbit of the family at ``sigma``: on each branch segment that
    brackets it, the orbit interpolated between its ends, and the ends' own."""
    out = []
    for ob in family.branches:
        if ob.problem.period_multiple != 1:
            continue
        p, b = ob.branch.p, ob.branch
        for i in range(len(p) - 1):
            if (p[i] - sigma) * (p[i + 1] - sigma) <= 0 and p[i] != p[i + 1]:
                w = (sigma - p[i]) / (p[i + 1] - p[i])
                A1 = (1 - w) * ob.measures["A1"][i] + w * ob.measures["A1"][i + 1]
                # the interpolated orbit first, then the segment's ends (a curved branch's chord
                # can miss where Newton converges)
                for y0 in ((1 - w) * b.x[i, :4] + w * b.x[i + 1, :4], b.x[i, :4], b.x[i + 1, :4]):
                    out.append((float(A1), y0))
    return out
