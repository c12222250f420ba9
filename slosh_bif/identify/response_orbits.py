"""The full model's side of a frequency-response fit: the stable 2pi-orbits of (9) at the data's
detunings and the amplitude A1 of their first harmonic (the A of eq. 25 that the slow flow
approximates), followed from one parameter set to the next.

At the first parameter set the family of 2pi-orbits is traced over the data's sigma range from a
start on the slow flow (:func:`~slosh_bif.orbits.families.trace_orbits`, with switching at its
pitchforks and period doublings); each point takes the orbit whose A1 is nearest its amplitude,
a stable one where there is one, by interpolation between the branch's points, corrected by Newton
at the point's own sigma. At any later parameter set each orbit is Newton's from the last one (the
least squares moves the parameters by small steps), stable or not (a fit started off the truth
may pass parameter sets where the measured orbit is unstable); :attr:`OrbitResponse.stable` says
which are stable at the last set, and an orbit Newton loses is reported, never replaced silently
by another.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import slow_flow_start

__all__ = ["OrbitResponse", "LostOrbit"]

SEGMENTS = 4  # arcs of each orbit's shooting problem


class LostOrbit(ValueError):
    """No orbit to follow at a data point, or Newton lost the one it followed."""


class OrbitResponse:
    """A1 of the stable 2pi-orbit of (9) that each point of ``data`` follows, at any parameter set
    near the first (:meth:`amplitudes`)."""

    def __init__(self, data, params: Params, progress=None):
        say = progress or (lambda message: None)
        self.sigma = np.asarray(data.sigma, dtype=float)
        lo, hi = float(self.sigma.min()), float(self.sigma.max())
        pad = 0.05 * (hi - lo) + 0.05
        say(f"orbits of (9): the family over sigma in [{lo - pad:.4g}, {hi + pad:.4g}]")
        start = slow_flow_start(params, lo - pad, hi + pad, segments=SEGMENTS)
        family = trace_orbits(
            start.params, start.y0, interval=ParameterRange(name="sigma", lo=lo - pad, hi=hi + pad)
        )
        self.data = data
        self.x, self.stable = [], []
        for problem, s, A in zip(self._problems(params), self.sigma, data.A):
            found = [_orbit(problem, problem.initial_states(y0, s), s) for _, y0 in _near(family, s)]
            found = [f for f in found if f is not None]
            if not found:
                raise LostOrbit(f"no 2pi-orbit of (9) found at sigma = {s:.6g} to follow")
            best = min(found, key=lambda f: (not f[2], abs(f[1] - A)))  # stable first, then nearest
            self.x.append(best[0])
            self.stable.append(best[2])

    def amplitudes(self, params: Params) -> np.ndarray:
        """A1 at each point's sigma for ``params``; :class:`LostOrbit` where an orbit is lost. The
        orbits found become the next call's starts."""
        found = [_orbit(problem, x, s) for problem, x, s in zip(self._problems(params), self.x, self.sigma)]
        lost = [s for f, s in zip(found, self.sigma) if f is None]
        if lost:
            raise LostOrbit(
                f"the orbits of (9) at sigma = {', '.join(f'{s:.4g}' for s in lost)} are lost at {params}"
            )
        self.x, self.stable = [f[0] for f in found], [f[2] for f in found]
        return np.array([f[1] for f in found])

    def _problems(self, params: Params) -> list:
        """Each point's shooting problem: one for all but data in Hz, whose points each have their
        own gamma and Abar."""
        if self.data.ratio is None:
            return [ShootingProblem(params, segments=SEGMENTS)] * len(self.sigma)
        return [
            ShootingProblem(self.data.params_at(params, i), segments=SEGMENTS) for i in range(len(self.sigma))
        ]


def _orbit(problem: ShootingProblem, x, sigma):
    """(x, A1, stable) of the orbit Newton finds from x at sigma, or None."""
    run = newton_solve(problem, x, sigma, tol=1e-10, max_iter=20, criterion="residual")
    if not run.converged:
        return None
    stable = bool(problem.is_stable(problem.eigenvalues(run.x, sigma)))
    return run.x, orbit_measures(problem, run.x, sigma)["A1"], stable


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
