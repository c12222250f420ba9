"""What the Floquet multipliers of a periodic orbit say, for orbits of (9) and of (8) alike: the
test functions of period doubling (or, on a half-period map, the symmetry-breaking pitchfork) and of
a Neimark-Sacker pair, and the confirmation of a located point.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DOUBLE", "TEST_FLOOR", "multiplier_tests", "describe_crossing", "is_stable"]

DOUBLE = 1e-5  # two multipliers this close to -1 (or a pair to +-1) are a double one, not a crossing
JUMP = 0.5  # a multiplier farther than this from -1 at a located PD/BP: the map jumped, nothing crossed

# An NS test value below this is zero to rounding, and a sign change with such a value at either
# end of the step is no crossing: a particle that stays off the walls is undamped to rounding (its
# damping lam w' w^(2p) is ~|w|^(2p)), its pair of multipliers stays on the unit circle to 1e-15,
# and the test (~1e-16 to 1e-14 along such a branch of the Fig. 13 set) flips sign from step to
# step. As the particle reaches the walls the pair moves inside, |mu| - 1 = -2e-11 to -2e-6 as the
# forcing rises by a quarter on the tank's fitted set (n = 50): a step from there to orbits off
# the walls can end on rounding of either sign (1.5e-11 at one end, -3e-16 at the other) without
# the pair ever leaving the circle. A genuine crossing, |mu| through 1 at a finite rate, gives
# values of order the step at both ends.
TEST_FLOOR = {"NS": 1e-11}


def is_stable(multipliers) -> bool:
    return bool(np.all(np.abs(multipliers) < 1))


def multiplier_tests(mu):
    """(a multiplier of the map through -1, a complex pair through the unit circle): the products
    ``prod(1 + mu)`` and ``prod_{i<j}(mu_i mu_j - 1)``, real and smooth in the map's entries."""
    n = len(mu)
    minus_one = np.prod(1 + mu).real
    pairs = [mu[i] * mu[j] - 1 for i in range(n) for j in range(i + 1, n)]
    return minus_one, np.prod(pairs).real


def describe_crossing(kind, mu, symmetric: bool):
    """What a located PD/BP/NS point is, from the map's multipliers ``mu`` (G's on a half-period
    map when ``symmetric``), or None when the sign change is no crossing (a double -1, or a
    neutral saddle for NS)."""
    if kind in ("PD", "BP"):
        k = int(np.argmin(np.abs(mu + 1)))
        if abs(mu[k] + 1) > JUMP:
            # no multiplier near -1: the test changed sign across a jump of the map's Jacobian (a
            # non-smooth point of an impact map: the measured law's clamp, say), not a crossing
            return None
        if np.min(np.abs(np.delete(mu, k) + 1)) < DOUBLE:
            # A double -1 is no simple crossing: off the walls at beta = 0 the particle drifts
            # freely (G has -1 twice all along), and the test's sign flips on rounding.
            return None
        if kind == "BP":
            return (
                f"symmetry-breaking pitchfork: the half-period map's multiplier {mu[k].real:.6f} "
                "through -1 (the period map's through +1)"
            )
        return f"period doubling: multiplier {mu[k].real:.6f} through -1"
    complex_pair = [m for m in mu if m.imag > 1e-7 * max(1.0, abs(m))]
    for m in complex_pair:
        if (
            abs(abs(m) - 1) < 1e-3 and min(abs(m - 1), abs(m + 1)) >= DOUBLE
        ):  # a pair split off a double +-1 by rounding is none
            angle = abs(np.angle(m * m if symmetric else m))  # the period map's pair
            return (
                f"Neimark-Sacker: multipliers exp(+-i {angle:.6f}) on the unit circle (rotation "
                f"{angle / (2 * np.pi):.6f})"
            )
    return None
