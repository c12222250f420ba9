"""The full model's side of a frequency-response fit: the stable 2pi-orbits of (9) at the data's
detunings and the amplitude A1 of their first harmonic (the A of eq. 25 that the slow flow
approximates), followed from one parameter set to the next.

At the first parameter set the family of 2pi-orbits is traced over the data's sigma range from a
start on the slow flow (:func:`~slosh_bif.orbits.families.trace_orbits`, with switching at its
pitchforks and period doublings); each point takes the stable orbit whose A1 is nearest its
amplitude, by interpolation between the branch's points, corrected by Newton at the point's own
sigma. At any later parameter set each orbit is Newton's from the last accepted one (the least
squares moves the parameters by small steps), its stability checked by its multipliers: an orbit
that is lost or no longer stable is reported, never replaced silently by another.
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
    """The orbit a data point follows has no stable continuation at this parameter set."""


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
        problem = ShootingProblem(params, segments=SEGMENTS)
        self.x = []
        for s, A in zip(self.sigma, data.A):
            guesses = sorted(_stable_near(family, s), key=lambda g: abs(g[0] - A))
            for _, y0 in guesses:
                found = _orbit(problem, problem.initial_states(y0, s), s)
                if found is not None:
                    self.x.append(found[0])
                    break
            else:
                raise LostOrbit(f"no stable 2pi-orbit of (9) found at sigma = {s:.6g} to follow")
        self.params = params

    def amplitudes(self, params: Params) -> np.ndarray:
        """A1 at each point's sigma for ``params``; :class:`LostOrbit` where an orbit is lost. The
        orbits found become the next call's starts."""
        problem = ShootingProblem(params, segments=SEGMENTS)
        found = [_orbit(problem, x, s) for x, s in zip(self.x, self.sigma)]
        lost = [s for f, s in zip(found, self.sigma) if f is None]
        if lost:
            raise LostOrbit(
                f"the stable orbits of (9) at sigma = {', '.join(f'{s:.4g}' for s in lost)} are lost at "
                f"{params}"
            )
        self.x = [f[0] for f in found]
        return np.array([f[1] for f in found])


def _orbit(problem: ShootingProblem, x, sigma):
    """(x, A1) of the stable orbit Newton finds from x at sigma, or None."""
    run = newton_solve(problem, x, sigma, tol=1e-10, max_iter=20, criterion="residual")
    if not run.converged or not problem.is_stable(problem.eigenvalues(run.x, sigma)):
        return None
    return run.x, orbit_measures(problem, run.x, sigma)["A1"]


def _stable_near(family, sigma) -> list:
    """(A1, y0) of each 2pi-orbit of the family at ``sigma`` that may be stable, interpolated
    between the points of a branch that bracket it (one of them stable: a special point between
    them is stable on one side only)."""
    out = []
    for ob in family.branches:
        if ob.problem.period_multiple != 1:
            continue
        p, b = ob.branch.p, ob.branch
        for i in range(len(p) - 1):
            bracket = (p[i] - sigma) * (p[i + 1] - sigma) <= 0 and p[i] != p[i + 1]
            if bracket and (b.stable[i] or b.stable[i + 1]):  # Newton's multipliers decide
                w = (sigma - p[i]) / (p[i + 1] - p[i])
                A1 = (1 - w) * ob.measures["A1"][i] + w * ob.measures["A1"][i + 1]
                y0 = (1 - w) * b.x[i, :4] + w * b.x[i + 1, :4]
                out.append((float(A1), y0))
    return out
