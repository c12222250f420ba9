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
orbit of a shorter period (a period-2 family that ends on its parent's grazing). Where another
contact of the orbit is near grazing too, the one-contact unfolding holds only within that
contact's own gap, so smaller sizes are tried after the usual ones.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import linalg

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.impact.band import law

__all__ = [
    "Contact",
    "contact_at",
    "unfold",
    "on_section",
    "grazing_by_unfolding",
    "cross_grazing",
    "repeats_sooner",
    "SAME_ORBIT",
    "sooner_return",
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
SAME_ORBIT = 1e-7  # two states of one orbit (on one section, at one parameter) agree within this (relative)


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


def cross_grazing(problem, x, p, opts, contact: Contact | None = None):
    """(problem, x, p, sign) of the branch beyond the grazing point (x, p) of ``problem`` (its
    ``contact``, when known): the orbit with the other contact at the least size in
    :data:`CONTACT_SIZES`, else the largest in :data:`NEAR_CONTACT_SIZES`, for which it is found
    and polished, its problem holding its own impact count, and the direction of p that leads away
    from the grazing; None when none is found within ``opts``' parameter bounds."""
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
        if count != problem.impacts and not repeats_sooner(probe, run.x, q):
            return problem.replace(impacts=count), run.x, q, 1.0 if q > p else -1.0
    return None


def repeats_sooner(problem, x, p) -> bool:
    """Whether the orbit through x at ``p``, a fixed point of the map over ``period_multiple``
    forcing periods, returns after a proper divisor of them: an orbit of a shorter period (the
    parent of a period doubling, say), not one of the problem's family."""
    return sooner_return(problem, x, p)[0] <= SAME_ORBIT


def sooner_return(problem, x, p) -> tuple:
    """(distance, periods): the least relative distance between the state x at ``p`` and its
    image after a proper divisor of the map's ``period_multiple`` forcing periods, and that
    divisor; (inf, 0) for a map over one forcing period."""
    m = problem.period_multiple
    x = np.asarray(x, dtype=float)
    best = (np.inf, 0)
    for d in (d for d in range(1, m) if m % d == 0):
        end = problem.phase + 2 * np.pi * d
        _, y, _, code = problem.flow_at(p).run(x, problem.phase, end, stick_speed=1e-9, max_impacts=10_000)
        if code == 0:
            best = min(best, (float(np.linalg.norm(y[:, -1] - x) / (1 + np.linalg.norm(x))), d))
    return best
