"""The vibro-impact model's side of a frequency-response fit: the stable 2pi-orbits of (8) (or of
the corrected impact model) at the data's detunings and the amplitude A1 of their first harmonic,
followed from one parameter set to the next: the fit by the paper's own model, whose error against
the slow flow (46) is the expansion's alone.

At the first parameter set each point's orbit is the impact-free response where it keeps inside the
walls, or the one a simulation of (8) settles on from the slow flow's motion (25), (29), (35) on its
stable steady state of (46) nearest the point's amplitude (then from the others, nearest first,
while the orbit found is unstable or its A1 more than :data:`FAR` off), the point taking the stable
orbit found that explains it best (:func:`~.assignment.pick`); Newton on the stroboscopic map
polishes it, and the map's section is moved to the middle of the orbit's longest flight, where an
impact does not cross it for small parameter changes. At any later set each orbit is Newton's
from the last (through intermediate sets where Newton from the last misses), stable or not, and
an orbit Newton loses is reported, never replaced silently by another (as
:mod:`.response_orbits` for (9)).
"""

from __future__ import annotations

import warnings

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.impact.flow import LINEAR_PARAMETERS, WALL_PARAMETERS, ImpactFlow
from slosh_bif.identify.assignment import pick
from slosh_bif.identify.response_model import impact_free, impact_free_state, response_curve
from slosh_bif.identify.response_orbits import SETTLE_MOST, SETTLED, LostOrbit, intermediate_sets
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import quiet_section, settled_orbit
from slosh_bif.orbits.impact.problem import VARIANT_NAMES, ImpactOrbitProblem
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow

__all__ = ["ImpactResponse", "first_harmonic_c1", "first_harmonic_derivative", "SETTLE", "FAR", "STEP"]

STEP = 0.02  # sample step of an orbit for A1: the corrected trapezoid's error ~ STEP**4 / 720
SETTLE = 100  # forcing periods simulated before Newton (doubled up to three times while unsettled)
NEUTRAL = 1e-8  # a multiplier this far outside the unit circle is on it (rounding)
FAR = 0.2  # an orbit whose A1 is this far (relative) from the point's amplitude: try another start


class ImpactResponse:
    """A1 of the stable 2pi-orbit of the impact model ``variant`` ("paper": (8); "corrected") that
    each point of ``data`` follows, at any parameter set near the first (:meth:`amplitudes`)."""

    def __init__(self, data, params: Params, progress=None, variant: str = "paper"):
        say = progress or (lambda message: None)
        self.variant, self.name = variant, VARIANT_NAMES[variant]
        self.sigma = np.asarray(data.sigma, dtype=float)
        say(f"orbits of {self.name}: from the slow flow's steady states at {len(self.sigma)} points")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AsymptoticsWarning)
            curve = response_curve(params) if data.ratio is None else None
        self.phase, self.x, self.stable = [None] * len(data), [None] * len(data), [None] * len(data)
        self.data, self.params = data, params
        self.candidates = [None] * len(data)  # (A1, stable) of every orbit found at each point
        self.found = [None] * len(data)  # (phase, x, A1, stable) of every orbit found at each point
        chosen = np.empty(len(data))
        for i, previous in data.sweep_order():
            s, at = self.sigma[i], data.params_at(params, i)
            A = float(data.A[i])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", AsymptoticsWarning)
                states = (curve or response_curve(at)).states_at(float(s))  # data in Hz: the point's set
            states = sorted(states, key=lambda st: (not st[1], abs(st[0] - A)))
            best, found_all = None, []
            # the impact-free response first where it keeps inside the walls: an orbit as it is
            free = [None] if impact_free(at)[1] < 1.0 else []
            for A0 in free + [A0 for A0, _ in states or [(float(A), False)]]:
                found = self._orbit(at, 0.0, impact_free_state(at)) if A0 is None else self._settle(at, A0)
                if found is not None:
                    found_all.append(found)
                    if best is None or _better(found, best, A):
                        best = found
                if best is not None and best[3] and abs(best[2] - A) <= FAR * A:
                    break
            if best is None:
                raise LostOrbit(
                    f"no 2pi-orbit of {self.name} found at sigma = {s:.6g} to follow: simulations from the "
                    "slow flow's steady states there settle on none (the response of the impact model there "
                    "may not be periodic; leave the point out or fit by another model)"
                )
            # the stable orbit that explains the point best, its sweep's continuing one where that
            # explains it nearly as well
            self.candidates[i], self.found[i] = [(f[2], f[3]) for f in found_all], found_all
            k = pick(data, i, None if previous is None else chosen[previous], self.candidates[i])
            best = found_all[k]
            self.phase[i], self.x[i], self.stable[i], chosen[i] = best[0], best[1], best[3], best[2]

    def _settle(self, at: Params, A0: float):
        """(phase, x, A1, stable) of the orbit a simulation from the slow flow's motion at amplitude
        A0 settles on, or None."""
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", AsymptoticsWarning)
                flow = SlowFlow(at)
                y0 = flow.fast_state(A0, float(flow.steady_phase(A0)), np.array([0.0]))[0]
        except ValueError:  # A0 off the manifold: start from the vessel's motion alone
            y0 = np.array([A0, 0.0, A0, 0.0])
        y0[2] = np.clip(y0[2], -1 + 1e-9, 1 - 1e-9)  # the particle inside the walls
        try:
            x = settled_orbit(at, y0, periods=SETTLE, tries=3, variant=self.variant)
        except Exception:  # noqa: BLE001 - a start that does not settle (ConvergenceError) or sticks
            return None
        problem = ImpactOrbitProblem(at, variant=self.variant)
        phase, x = quiet_section(problem, x, at.sigma)
        return self._orbit(at, phase, x)

    def settled_from_rest(self, i: int) -> list:
        """[(phase, x, A1, stable)] of the orbit a simulation from rest settles on at point i's set
        (the one the last call left): Newton only once the strobe a period apart agrees to
        :data:`~.response_orbits.SETTLED`, or [] where it settles on no stable orbit within
        :data:`~.response_orbits.SETTLE_MOST` periods (as :mod:`.response_orbits` for (9))."""
        at = self.data.params_at(self.params, i)
        problem = ImpactOrbitProblem(at, variant=self.variant)
        flow, y = problem.flow_at(at.sigma), np.zeros(4)
        for _ in range(SETTLE_MOST // SETTLE):
            ends = []
            for periods in (SETTLE - 1, 1):
                _, states, _, code = flow.run(
                    y, 0.0, 2 * np.pi * periods, stick_speed=1e-9, max_impacts=10**7
                )
                if code != 0:  # sticks, or leaves the measured law: no orbit from rest
                    return []
                y = states[:, -1]
                ends.append(y)
            if np.max(np.abs(ends[1] - ends[0])) <= SETTLED * (1.0 + np.max(np.abs(y))):
                found = self._orbit(at, *quiet_section(problem, y, at.sigma))
                return [found] if found is not None and found[3] else []
        return []

    def _orbit(self, params: Params, phase: float, x):
        """(phase, x, A1, stable) of the orbit Newton finds from x on the section at ``phase``."""
        problem = ImpactOrbitProblem(params, phase=phase, variant=self.variant)
        run = newton_solve(problem, x, params.sigma, tol=1e-11, max_iter=20, criterion="residual")
        if not run.converged or not problem.in_domain(run.x, params.sigma):
            return None
        mu = problem.eigenvalues(run.x, params.sigma)
        # an orbit without impacts has the particle's undamped relative mode, multipliers on the
        # unit circle: neutrally stable (a family of such orbits), which a sweep can stay on
        free = len(problem.evaluate(run.x, params.sigma).impacts) == 0
        stable = bool(problem.is_stable(mu)) or (free and float(np.max(np.abs(mu))) <= 1.0 + NEUTRAL)
        t, y, _ = problem.orbit(run.x, params.sigma, step=STEP)
        return phase, run.x, first_harmonic_c1(t, y[0], y[1]), stable

    def state(self):
        """What the next call starts from (each orbit on its section), for :meth:`restore`."""
        return list(self.x), list(self.stable), self.params

    def restore(self, state) -> None:
        self.x, self.stable, self.params = list(state[0]), list(state[1]), state[2]

    def amplitudes(self, params: Params) -> np.ndarray:
        """A1 at each point's sigma for ``params``; :class:`LostOrbit` where an orbit is lost. The
        orbits found become the next call's starts."""
        found = [
            self._orbit(self.data.params_at(params, i), phase, x)
            for i, (phase, x) in enumerate(zip(self.phase, self.x))
        ]
        for i in [i for i, f in enumerate(found) if f is None]:
            found[i] = self._followed(i, params)
        lost = [s for f, s in zip(found, self.sigma) if f is None]
        if lost:
            where = ", ".join(f"{s:.4g}" for s in lost)
            raise LostOrbit(f"the orbits of {self.name} at sigma = {where} are lost at {params}")
        self.x, self.stable = [f[1] for f in found], [f[3] for f in found]
        self.params = params
        return np.array([f[2] for f in found])

    def _followed(self, i: int, params: Params):
        """Point i's orbit at ``params`` followed from the last set's through the sets in between
        (:func:`~.response_orbits.intermediate_sets`), or None."""
        x, found = self.x[i], None
        for at in intermediate_sets(self.params, params):
            found = self._orbit(self.data.params_at(at, i), self.phase[i], x)
            if found is None:
                return None
            x = found[1]
        return found

    def differentiates(self, names) -> bool:
        """Whether :meth:`gradient` has every name: the flights' parameters, and for (8) the wall's
        lam and chi (the measured wall's law has no derivatives in its parameters)."""
        allowed = LINEAR_PARAMETERS + (WALL_PARAMETERS if self.variant == "paper" else ())
        return all(name in allowed for name in names)

    def gradient(self, names) -> np.ndarray:
        """dA1/d(``names``) at each point, shape (points, len(names)), at the parameter set of the
        last :meth:`amplitudes` call, the orbits moving with the parameters: from the flow's own
        sensitivities along each orbit (:func:`first_harmonic_derivative`), not from differences
        of orbits."""
        rows = []
        for i, (phase, x) in enumerate(zip(self.phase, self.x)):
            at = self.data.params_at(self.params, i)
            row = []
            for name in names:
                ((param, weight),) = self.data.direction_at(i, name).items()
                row.append(weight * first_harmonic_derivative(at, param, phase, x, self.variant))
            rows.append(row)
        return np.array(rows)


def first_harmonic_derivative(params: Params, param: str, phase: float, x, variant: str = "paper") -> float:
    """dA1/d``param`` of the 2pi-orbit through x on the section ``phase``, the orbit moving with
    the parameter: x = P(x, p) gives (I - M) dx/dp = dP/dp (M the saltation monodromy), the state
    along the orbit moves by Phi(t) dx/dp + s(t) (the flow's own sensitivities at every sample,
    impacts included), and A1's quadrature is differentiated as it stands (linear in X, X')."""
    flow = ImpactFlow(params, STEP, param=param, variant=variant)
    t, y, phis, dps, _, code = flow.sensitivities(np.asarray(x, dtype=float), phase, 2 * np.pi)
    if code != 0:
        raise LostOrbit(f"the orbit at sigma = {params.sigma:.4g} ends early (code {code})")
    dx = np.linalg.solve(np.eye(4) - phis[-1], dps[-1])
    dy = phis @ dx + dps
    c1, dc1 = _c1(t, y[0], y[1]), _c1(t, dy[:, 0], dy[:, 1])
    return float((np.conj(c1) * dc1).real / abs(c1))


def _c1(t, X, Xd) -> complex:
    """The forcing frequency's Fourier coefficient of X (times 2) over the period sampled at t: the
    trapezoid rule with its end correction on each interval (:func:`first_harmonic_c1`)."""
    e = np.exp(-1j * t)
    f, df = X * e, (Xd - 1j * X) * e
    h = np.diff(t)
    integral = np.sum(0.5 * h * (f[1:] + f[:-1]) + h * h / 12.0 * (df[:-1] - df[1:]))
    return complex(integral / (0.5 * (t[-1] - t[0])))


def first_harmonic_c1(t, X, Xd) -> float:
    """A1 of X over the whole period sampled at t (the impact instants among them), by the
    trapezoid rule with its end correction h**2/12 (f'(a) - f'(b)) on each interval, f = X e^(-i t):
    fourth order where X is C1 (the vessel's speed does not jump at an impact of (8), its
    acceleration does, and the impacts are sample points), so that A1 is smooth to ~1e-10 in the
    parameters, as the least squares' differences need (a sampled trapezoid's 1e-5 is not)."""
    return abs(_c1(t, X, Xd))


def _better(found, best, A) -> bool:
    """Whether ``found`` beats ``best`` for a point of amplitude A: stable first, then nearer."""
    return (not found[3], abs(found[2] - A)) < (not best[3], abs(best[2] - A))
