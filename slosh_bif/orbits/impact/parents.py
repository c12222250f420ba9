"""The parent a family of orbits of (8) is born from (eqs. 8, 21), met again at a grazing.

A period-m family (a fixed point of the map over m forcing periods) is born at its parent's period
doubling, an orbit that returns after fewer periods; an asymmetric family is born at its parent's
pitchfork, a symmetric orbit, whose mirror image half a period on, y -> -y(tau + pi), is itself. A
family's own orbits are neither, but where it meets its parent at the parent's grazing, the orbits
the contact's unfolding finds beyond are the parent's: they are refused there, and a family whose
grazing orbit lies on its parent ends on it (the rest of the parent's branch is its own).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "SAME_ORBIT",
    "NEAR_PARENT",
    "sooner_return",
    "mirror_return",
    "repeats_sooner",
    "is_asymmetric",
    "on_parent",
    "parent_met",
]

SAME_ORBIT = 1e-7  # two states of one orbit (on one section, at one parameter) agree within this (relative)
NEAR_PARENT = 1e-3  # a grazing orbit this near (relative) to its parent is on it
ASYMMETRIC = 1e-6  # an orbit this far (relative) from its mirror image is asymmetric


def _distance(problem, x, p, span: float, sign: float) -> float:
    """The relative distance between x and ``sign`` times its image ``span`` later; inf where the
    flow stops short."""
    _, y, _, code = problem.flow_at(p).run(
        x, problem.phase, problem.phase + span, stick_speed=1e-9, max_impacts=10_000
    )
    return float(np.linalg.norm(sign * y[:, -1] - x) / (1 + np.linalg.norm(x))) if code == 0 else np.inf


def sooner_return(problem, x, p) -> tuple:
    """(distance, periods): the least relative distance between the state x at ``p`` and its
    image after a proper divisor of the map's ``period_multiple`` forcing periods, and that
    divisor; (inf, 0) for a map over one forcing period."""
    m = problem.period_multiple
    x = np.asarray(x, dtype=float)
    found = [(_distance(problem, x, p, 2 * np.pi * d, 1.0), d) for d in range(1, m) if m % d == 0]
    return min(found, default=(np.inf, 0))


def mirror_return(problem, x, p) -> float:
    """The least relative distance between the state x at ``p`` and its mirror image an odd
    number of half forcing periods on, within the map's period (a symmetric orbit's is zero); inf
    on the half-period map (symmetric by construction)."""
    if problem.closing < 0:
        return np.inf
    x = np.asarray(x, dtype=float)
    return min(_distance(problem, x, p, np.pi * (2 * k + 1), -1.0) for k in range(problem.period_multiple))


def repeats_sooner(problem, x, p) -> bool:
    """Whether the orbit through x at ``p``, a fixed point of the map over ``period_multiple``
    forcing periods, returns after a proper divisor of them: an orbit of a shorter period (the
    parent of a period doubling, say), not one of the problem's family."""
    return sooner_return(problem, x, p)[0] <= SAME_ORBIT


def is_asymmetric(problem, x, p) -> bool:
    """Whether the orbit through x at ``p`` is asymmetric: a family through it is an asymmetric
    family (a symmetric orbit can be traced on the whole-period map as well); False on the
    half-period map."""
    return problem.closing > 0 and mirror_return(problem, x, p) > ASYMMETRIC


def on_parent(problem, x, p, asymmetric: bool) -> bool:
    """Whether the orbit through x at ``p`` is an orbit of a shorter period or, for an
    ``asymmetric`` family, a symmetric one: its parent's, not one of the family."""
    return repeats_sooner(problem, x, p) or (asymmetric and mirror_return(problem, x, p) <= SAME_ORBIT)


def parent_met(problem, x, p, asymmetric: bool) -> str | None:
    """How the grazing orbit x at ``p`` lies on the family's parent, within :data:`NEAR_PARENT`
    (a phrase), or None where it does not."""
    distance, periods = sooner_return(problem, x, p)
    if distance <= NEAR_PARENT:
        return f"an orbit of period {periods} (within {distance:.1g} of returning after it)"
    mirror = mirror_return(problem, x, p) if asymmetric else np.inf
    if mirror <= NEAR_PARENT:
        return f"a symmetric orbit (within {mirror:.1g} of its mirror image half a period on)"
    return None
