"""The least forcing Abar at one sigma with a stable 2pi-periodic response of (9) in wall contact
(max |w| >= 1): the critical forcing Abar_c of the full model, the counterpart of the slow flow's
Abar_b of (46). It is the lower end of the stable orbits with contact, which is one of

- a special point (LP, PD, NS, BP) below which the orbits are unstable or absent;
- a contact crossing: the stable orbit stops touching the walls smoothly as Abar falls, which in
  (9) is no bifurcation (no stability is lost; ``loss`` "none");
- the bottom of the range: stable orbits with contact reach it, and Abar_c lies below.

A curve of bifurcations bounds stable orbits on one side only. Where the stable side is below the
curve (a pitchfork whose symmetric orbit stays stable beneath it, a torus point of an orbit stable
below), the lower end is further down: :func:`stable_side_below` follows it there.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import optimize

from slosh_bif.continuation.options import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.orbit_branch import OrbitBranch
from slosh_bif.orbits.orbit_tools import orbit_at, orbit_measures
from slosh_bif.orbits.settings import NO_SWITCHING, SHOOTING, ParameterRange, ShootingSettings
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = [
    "LowEnd",
    "along_bottom",
    "born_at",
    "family_low_ends",
    "lowest_stable_contact",
    "stable_orbit_below",
    "stable_side_below",
    "BELOW_STEP",
    "FINE_POINTS",
]

BELOW_STEP = 1e-3  # the side below a curve point is probed at Abar (1 - BELOW_STEP)
# Newton steps of a probe: an orbit 1e-3 below a PD, NS or BP point, or 3e-2 below a fold, is
# found in a few; above a fold opening upwards there is none, and each further step is an
# integration of the variational equations
PROBE_ITERATIONS = 8
ABOVE = 0.05  # the branch below a curve point is traced up to Abar (1 + ABOVE)
FINE_POINTS = 4096  # samples per 2pi of max |w| at a contact crossing (the peak's error ~ 1e-7)
_BOUNDS = ("LP", "PD", "NS", "BP")


@dataclasses.dataclass(frozen=True)
class LowEnd:
    """The lower end of the stable orbits with wall contact on a branch in Abar: ``Abar`` (NaN
    where ``below_range``: they reach the range's bottom), ``kind`` (a special point's kind,
    "contact" for a contact crossing, "unlocated" where stability changes between two points with
    no special point located), ``index`` of the special point on ``branch`` (-1 for none)."""

    Abar: float
    kind: str
    branch: OrbitBranch
    index: int = -1
    below_range: bool = False


def lowest_stable_contact(ob: OrbitBranch, a0: float) -> LowEnd | None:
    """The lower end of the stable orbits with wall contact on the period-1 branch ``ob`` (in
    Abar), over a range whose bottom is ``a0``; None where it has none."""
    b = ob.branch
    good = np.asarray(b.stable, dtype=bool) & (ob["max_abs_w"] >= 1.0)
    if not good.any():
        return None
    p = np.asarray(b.p, dtype=float)
    i = int(np.argmin(np.where(good, p, np.inf)))
    if p[i] <= a0 + 1e-9 * (1 + abs(a0)):
        return LowEnd(np.nan, "", ob, below_range=True)
    bounding = [
        (sp.p, j)
        for j, sp in enumerate(b.special)
        if sp.kind in _BOUNDS and sp.located and sp.index in (i - 1, i) and sp.p <= p[i]
    ]
    if bounding:
        value, j = min(bounding)
        return LowEnd(float(value), b.special[j].kind, ob, j)
    lower = [k for k in (i - 1, i + 1) if 0 <= k < len(p) and p[k] < p[i]]
    if lower and b.stable[lower[0]]:  # stable there, without contact
        return LowEnd(_contact_crossing(ob, lower[0], i), "contact", ob)
    return LowEnd(float(p[i]), "unlocated", ob)


def born_at(end: LowEnd, branches) -> LowEnd:
    """Where ``end`` is the first (or last) point of a switched branch, its stable orbits start
    where it was switched on: the located BP of another of ``branches`` at that Abar (within
    1e-3), with its own index there; ``end`` itself otherwise. The switched branch's first point
    lies a step off the pitchfork (5e-5 on the seed-28 set), where nothing is located."""
    ob = end.branch
    if end.kind != "unlocated" or not ob.origin or end.Abar not in (ob.branch.p[0], ob.branch.p[-1]):
        return end
    near = [
        (abs(sp.p - end.Abar), k, j)
        for k, other in enumerate(branches)
        if other is not ob
        for j, sp in enumerate(other.branch.special)
        if sp.kind == "BP" and sp.located
    ]
    if not near or min(near)[0] > 1e-3 * (1 + abs(end.Abar)):
        return end
    _, k, j = min(near)
    return LowEnd(float(branches[k].branch.special[j].p), "BP", branches[k], j)


def family_low_ends(branches, a0: float) -> list:
    """The lower end of the stable orbits with wall contact on each period-1 branch of
    ``branches`` that has them (:func:`lowest_stable_contact`, a switched pair's at its parent's
    pitchfork by :func:`born_at`)."""
    period_1 = [ob for ob in branches if ob.problem.period_multiple == 1]
    return [born_at(e, period_1) for ob in period_1 for e in [lowest_stable_contact(ob, a0)] if e is not None]


def along_bottom(ob: OrbitBranch, at: Params, a0: float, sigma_range, shooting: ShootingSettings = SHOOTING):
    """(sigma, good) of the branch in sigma at Abar = ``a0`` through the lowest stable orbit with
    wall contact of ``ob`` (a branch in Abar at ``at``'s sigma whose stable orbits with contact
    reach ``a0``, the range's bottom), traced over ``sigma_range``: ``good`` where its orbits are
    stable with contact, so that Abar_c lies below ``a0`` there; None where it cannot be traced."""
    b = ob.branch
    good = np.asarray(b.stable, dtype=bool) & (ob["max_abs_w"] >= 1.0)
    if not good.any():
        return None
    i = int(np.argmin(np.where(good, b.p, np.inf)))
    try:
        family = trace_orbits(
            at.replace(Abar=float(b.p[i])),  # a0 as the branch located its end
            b.x[i, :4],
            interval=ParameterRange(lo=float(sigma_range[0]), hi=float(sigma_range[1])),
            shooting=shooting,
            branching=NO_SWITCHING,
        )
    except (ConvergenceError, ValueError):
        return None
    edge = family.branches[0]
    return np.asarray(edge.branch.p, dtype=float), np.asarray(edge.branch.stable, dtype=bool) & (
        edge["max_abs_w"] >= 1.0
    )


def _contact_crossing(ob: OrbitBranch, lo: int, hi: int) -> float:
    """Abar where max |w| = 1 between the branch's points ``lo`` (no contact) and ``hi``
    (contact), by Brent's method on Newton-corrected orbits (the linear interpolation of max |w|
    where that fails)."""
    b, problem = ob.branch, ob.problem
    p0, p1 = float(b.p[lo]), float(b.p[hi])

    def excess(a):
        t = (a - p0) / (p1 - p0)
        orbit = orbit_at(problem, b.x[lo] + t * (b.x[hi] - b.x[lo]), a)
        if not orbit.converged:
            raise ConvergenceError(orbit.message)
        x = problem.initial_states(orbit.y0)
        return orbit_measures(problem, x, a, points_per_2pi=FINE_POINTS)["max_abs_w"] - 1.0

    try:
        f0, f1 = excess(p0), excess(p1)
        if f0 < 0 <= f1:
            return float(optimize.brentq(excess, p0, p1, xtol=1e-12 * (1 + abs(p1)), rtol=1e-12))
    except (ConvergenceError, ValueError):
        pass
    w = ob["max_abs_w"]
    return float(p0 + (1.0 - w[lo]) / (w[hi] - w[lo]) * (p1 - p0))


def stable_orbit_below(
    params: Params, y0, a0: float, *, fold: bool = False, shooting: ShootingSettings = SHOOTING
):
    """The stable period-1 orbit with wall contact just below the curve point (``params.sigma``,
    ``params.Abar``) whose orbit passes through ``y0``: Newton at Abar (1 - :data:`BELOW_STEP`)
    from it (at a ``fold``, from it and reflected through it: the fold's two orbits there); None
    where there is none (the stable side is above, or no orbit is found below) or below ``a0``."""
    below = params.Abar * (1 - BELOW_STEP)
    if not below > a0:
        return None
    problem = ShootingProblem(
        params.replace(Abar=below),
        "Abar",
        segments=shooting.segments,
        rtol=shooting.rtol,
        atol=shooting.atol,
        backend=shooting.backend,
    )
    x0 = problem.initial_states(np.asarray(y0, dtype=float))
    first = orbit_at(problem, x0, below, max_iter=PROBE_ITERATIONS)
    if _stable_with_contact(problem, first, below):
        return first
    if fold and first.converged:
        other = orbit_at(problem, 2 * x0 - problem.initial_states(first.y0), below, max_iter=PROBE_ITERATIONS)
        if _stable_with_contact(problem, other, below):
            return other
    return None


def stable_side_below(params: Params, orbit, a0: float, shooting: ShootingSettings = SHOOTING):
    """The lower end of the stable orbits with wall contact on the branch in Abar through
    ``orbit``, the one :func:`stable_orbit_below` found below the curve point ``params`` (None
    for none), traced down to ``a0``; None where there is no orbit or its branch fails."""
    if orbit is None:
        return None
    value = params.Abar
    try:
        family = trace_orbits(
            params.replace(Abar=value * (1 - BELOW_STEP)),
            orbit.y0,
            # room above the curve point: a fold just below it is located, not cut by the range's end
            interval=ParameterRange(lo=a0, hi=value * (1 + ABOVE), name="Abar"),
            shooting=shooting,
            branching=NO_SWITCHING,
        )
    except (ConvergenceError, ValueError):
        return None
    return lowest_stable_contact(family.branches[0], a0)


def _stable_with_contact(problem: ShootingProblem, orbit, p) -> bool:
    """Whether the Newton result ``orbit`` at ``p`` converged to a stable orbit in wall contact."""
    if not (orbit.converged and orbit.stable):
        return False
    return orbit_measures(problem, problem.initial_states(orbit.y0), p)["max_abs_w"] >= 1.0
