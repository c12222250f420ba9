"""Crossing a grazing point of a branch of orbits of (8) (eqs. 8, 21): the orbit on the other side,
attracting or not, from the contact's own unfolding.

At a grazing orbit (GR) the particle touches the wall with zero speed at tau = t_g. Near it, the
map of (8) at a section is not smooth: a new impact of speed v has a saltation matrix of size 1/v,
and Newton from the grazing orbit falls back to the side it came from. The orbits themselves are
smooth families when written at the contact, with the state ``y_c = [X, X', w_c, w'_c]`` at
tau = t_c and one of two contacts fixed:

* ``"flight"``: a turning point short of the wall by a gap g, ``w_c = side (L - g)``, ``w'_c = 0``
  (L the wall's level: 1, or the measured wall's least clearance);
* ``"impact"``: an impact of speed v, ``w_c = side D(v)``, ``w'_c = side v`` (D = 1 for (8) as
  stated), after which the restitution law sets ``w'+ = -kappa(v) w'_c``.

Four equations close the orbit, its return to ``y_c`` over the period (free flights of
:data:`FREE` on each side of the contact, the compiled flow between, the mirror for a symmetric
orbit), in the unknowns (X, X', t_c, p) at fixed g or v; g = v = 0 is the grazing orbit itself.
Generically p moves linearly in g and in v, so the family beyond exists on one side of the grazing
parameter only, and which side it is comes out of the solve (the side the branch came from: a
non-smooth fold). The solve uses central differences (four unknowns, a few map evaluations); the
orbit found is then polished by Newton on the section's map with its exact saltation Jacobian,
which also checks that it is an orbit of (8) with the impact count the contact says, and not an
orbit of its family's parent (:mod:`slosh_bif.orbits.impact.parents`). Where another contact of
the orbit is near grazing too, the one-contact unfolding holds only within that contact's own gap,
so smaller sizes are tried after the usual ones. Where the unfolding fails at every size, the map's
own iterates are tried for an attracting orbit beyond (:func:`attracting_beyond`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import linalg

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.impact.band import law
from slosh_bif.orbits.impact.parents import on_parent

__all__ = [
    "Contact",
    "contact_at",
    "unfold",
    "on_section",
    "grazing_by_unfolding",
    "cross_grazing",
    "attracting_beyond",
    "CONTACT_SIZES",
    "NEAR_CONTACT_SIZES",
    "FREE",
]

FREE = 0.1  # the flights beside the contact, in tau, taken with the wall ignored
CONTACT_SIZES = (1e-3, 1e-2)  # gaps or impact speeds tried in turn beyond a grazing point
# tried after those: where another contact of the orbit is itself near grazing, the one-contact
# unfolding holds only that near (a second impact appears at a larger size)
NEAR_CONTACT_SIZES = (1e-4, 1e-5, 1e-6)
_NEWTON_STEPS = 25
CROSSING_STEPS = (1e-6, 1e-5, 1e-4, 1e-3)  # parameter steps beyond a grazing point, tried in turn
CROSSING_ITERATES = 300  # iterates of the map beyond a grazing point before Newton
NEAR_GRAZING = 10.0  # an orbit beyond a grazing counts as its continuation within this times sqrt(step)


@dataclasses.dataclass(frozen=True)
class Contact:
    """The contact of a grazing orbit: time ``t``, wall ``side`` (+-1), the vessel's state (X, X')
    there, and ``kind``: "flight" (the branch had no impact there: beyond it one is added) or
    "impact" (an impact whose speed fell to zero: beyond it the flight turns short of the wall)."""

    t: float
    side: float
    X: float
    Xd: float
    kind: str

    @property
    def beyond(self) -> str:
        """The contact of the family on the other side of the grazing."""
        return "impact" if self.kind == "flight" else "flight"

    def same_as(self, other: Contact, p: float, q: float, tol: float = 1e-7) -> bool:
        """Whether this contact at p is ``other``'s at q, or its mirror image (tau -> tau + pi,
        y -> -y: the same family, or its mirror traced again)."""
        if abs(p - q) > tol:
            return False
        for shift, sign in ((0.0, 1.0), (np.pi, -1.0)):
            dt = (self.t - other.t - shift + np.pi) % (2 * np.pi) - np.pi
            near = abs(self.X - sign * other.X) + abs(self.Xd - sign * other.Xd)
            if abs(dt) < 1e-6 and self.side == sign * other.side and near < tol * (1 + abs(self.X)):
                return True
        return False


def contact_at(problem, x, p, gap=None) -> Contact:
    """The contact of the grazing orbit x at p (a GR point of ``problem``, an ImpactOrbitProblem);
    ``gap``: its ``problem.grazing(x, p)`` where already measured."""
    gap = problem.grazing(x, p) if gap is None else gap
    flow = problem.flow_at(p)
    start = problem.phase
    y = np.asarray(x, dtype=float)
    if gap.t > start + 1e-12:
        y = flow.run(y, start, gap.t, stick_speed=1e-9, max_impacts=10_000)[1][:, -1]
    return Contact(float(gap.t), 1.0 if y[2] >= 0 else -1.0, float(y[0]), float(y[1]), gap.kind)


def _wall(flow, v):
    """(kappa, D) of the flow's wall at impact speed v (the measured law clamped as the flow clamps
    it); kappa NaN where (21) has no real value at v (pbar < 0: slow impacts lose without bound),
    which makes the caller's residual NaN."""
    if flow.wall is None:
        square = 1.0 - flow.kappa_c * v**flow.kappa_q
        return (np.sqrt(square) if square >= 0 else np.nan), 1.0
    kappa, _, clearance, _ = law(flow.shape, flow.stacked, v)
    return kappa, clearance


class _Unfolding:
    """The closing equations of the orbits with one contact of kind ``kind`` and size ``size``."""

    def __init__(self, problem, side: float, kind: str, size: float):
        self.problem, self.side, self.kind, self.size = problem, side, kind, size
        self._free: dict = {}

    def _propagator(self, p, flow):
        if p not in self._free:
            self._free = {p: linalg.expm(flow.K * FREE)}
        return self._free[p]

    def contact_states(self, u):
        """(state at the contact as the orbit arrives, state as it leaves) for u = (X, X', t_c, p)."""
        flow = self.problem.flow_at(u[3])
        s = self.side
        if self.kind == "flight":
            y = np.array([u[0], u[1], s * (flow.grazing_level - self.size), 0.0])
            return y, y
        kappa, clearance = _wall(flow, self.size)
        arriving = np.array([u[0], u[1], s * clearance, s * self.size])
        return arriving, np.array([u[0], u[1], s * clearance, -kappa * s * self.size])

    def leaving(self, u):
        """The state at tau = t_c + FREE."""
        flow = self.problem.flow_at(u[3])
        t = float(u[2])
        _, post = self.contact_states(u)
        return (self._propagator(u[3], flow) @ np.concatenate([post, [np.cos(t), np.sin(t)]]))[:4]

    def residual(self, u):
        """The orbit's return to its contact state; NaN where it cannot be evaluated (a parameter
        set that does not exist, a flow that stops short)."""
        if not np.all(np.isfinite(u)):
            return np.full(4, np.nan)
        try:
            return self._residual(u)
        except ValueError:
            return np.full(4, np.nan)

    def _residual(self, u):
        problem, t = self.problem, float(u[2])
        flow = problem.flow_at(u[3])
        arriving, _ = self.contact_states(u)
        rest = problem.period - 2 * FREE
        _, y, _, code = flow.run(
            self.leaving(u), t + FREE, t + FREE + rest, stick_speed=1e-9, max_impacts=10_000
        )
        if code != 0:
            return np.full(4, np.nan)
        back = t + problem.period - FREE
        end = self._propagator(u[3], flow) @ np.concatenate([y[:, -1], [np.cos(back), np.sin(back)]])
        return problem.closing * end[:4] - arriving


def unfold(problem, contact: Contact, p: float, kind: str, size: float):
    """(X, X', t_c, p) of the orbit with a contact of ``kind`` and ``size`` (gap or impact speed)
    near the grazing orbit of ``contact`` at ``p``, or None where Newton does not converge."""
    equations = _Unfolding(problem, contact.side, kind, size)
    u = np.array([contact.X, contact.Xd, contact.t, p])
    for _ in range(_NEWTON_STEPS):
        F = equations.residual(u)
        if not np.all(np.isfinite(F)):
            return None
        if np.abs(F).max() < 1e-12:
            return u, equations
        J = np.empty((4, 4))
        for j in range(4):
            e = np.zeros(4)
            e[j] = 1e-7 * max(1.0, abs(u[j]))
            J[:, j] = (equations.residual(u + e) - equations.residual(u - e)) / (2 * e[j])
        if not np.all(np.isfinite(J)):
            return None
        try:
            u = u - np.linalg.solve(J, F)
        except np.linalg.LinAlgError:
            return None
    return (u, equations) if np.abs(equations.residual(u)).max() < 1e-10 else None


def on_section(problem, equations, u):
    """The state on the problem's section tau = phase (mod its period) of the unfolded orbit u."""
    t = float(u[2])
    k = int(np.ceil((t + FREE - problem.phase) / problem.period - 1e-12))
    target = problem.phase + k * problem.period
    flow = problem.flow_at(u[3])
    y = flow.run(equations.leaving(u), t + FREE, target, stick_speed=1e-9, max_impacts=10_000)[1][:, -1]
    return problem.closing**k * y


def grazing_by_unfolding(problem, x, p):
    """(x, p) of the grazing orbit near (x, p), on the problem's section, from the contact's
    unfolding at zero gap (smooth where the section's map is not: reached from an impact whose
    speed falls to zero), or None where it does not converge."""
    found = unfold(problem, contact_at(problem, x, p), p, "flight", 0.0)
    if found is None:
        return None
    u, equations = found
    y = on_section(problem, equations, u)
    return (y, float(u[3])) if problem.admissible(y, u[3]) else None


def cross_grazing(problem, x, p, opts, contact: Contact | None = None, asymmetric: bool = False):
    """(problem, x, p, sign) of the branch beyond the grazing point (x, p) of ``problem`` (its
    ``contact``, when known): the orbit with the other contact at the least size in
    :data:`CONTACT_SIZES`, else the largest in :data:`NEAR_CONTACT_SIZES`, for which it is found
    and polished, its problem holding its own impact count, and the direction of p that leads away
    from the grazing; None when none is found within ``opts``' parameter bounds. An orbit of the
    family's parent (a shorter period; a symmetric one for an ``asymmetric`` family) is refused."""
    contact = contact or contact_at(problem, x, p)
    probe = problem.replace(impacts=None)
    # the located point may sit on either side of the contact (an impact of speed ~0, or a flight
    # turning at the wall): the family beyond is the one whose impact count differs from the branch's
    kinds = (contact.beyond, contact.kind)
    tries = [(k, s) for sizes in (CONTACT_SIZES, NEAR_CONTACT_SIZES) for k in kinds for s in sizes]
    for kind, size in tries:
        found = unfold(problem, contact, p, kind, size)
        if found is None:
            continue
        u, equations = found
        q = float(u[3])
        if q == p or not opts.p_min <= q <= opts.p_max:
            continue
        run = newton_solve(probe, on_section(problem, equations, u), q, tol=1e-12)
        if not (run.converged and probe.in_domain(run.x, q)):
            continue
        count = len(probe.evaluate(run.x, q).impacts)
        if count != problem.impacts and not on_parent(probe, run.x, q, asymmetric):
            return problem.replace(impacts=count), run.x, q, 1.0 if q > p else -1.0
    return None


def attracting_beyond(problem, x, p, sign, opts, asymmetric: bool = False):
    """(problem, x, p, sign) of an attracting orbit just beyond a grazing point, on a problem
    holding its own impact count, or None: the fallback where the unfolding fails. The map's own
    iterates from the grazing orbit give the guess that Newton then polishes; an orbit of the
    family's parent is refused as in :func:`cross_grazing`."""
    for step in CROSSING_STEPS:
        q = p + sign * step
        if not opts.p_min <= q <= opts.p_max:
            return None
        probe = problem.replace(impacts=None)
        guess = np.asarray(x, dtype=float)
        for _ in range(CROSSING_ITERATES):
            m = probe.evaluate(guess, q)
            if m.code != 0:
                break
            guess = m.y
        run = newton_solve(probe, guess, q, tol=1e-12)
        # the orbit beyond moves away from the grazing one as the square root of the step (the
        # new impact's speed); one farther off is another attractor, not the branch's continuation
        near = np.linalg.norm(run.x - x) <= NEAR_GRAZING * np.sqrt(step) * (1.0 + np.linalg.norm(x))
        # and only an attracting one: where the iterates wander (no attractor beyond), Newton's
        # landing place depends on rounding, and an unstable orbit it finds is left alone
        if (
            run.converged
            and near
            and probe.in_domain(run.x, q)
            and probe.is_stable(probe.eigenvalues(run.x, q))
        ):
            count = len(probe.evaluate(run.x, q).impacts)
            if count != problem.impacts and not on_parent(probe, run.x, q, asymmetric):
                return problem.replace(impacts=count), run.x, q, sign
    return None
