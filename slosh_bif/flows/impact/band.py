"""The corrected impact model's wall: the smooth wall's own restitution kappa_wall(v) and its
clearance D(v) (:mod:`slosh_bif.model.restitution.wall`) in place of (21) and |w| = 1 in (8).

The wall is the surface ``g(y) = side * w - D(v) = 0``, v = side * w' the speed towards it: where it
stands depends on the speed the particle arrives with. Below the measured speeds (v < v_min, and
when the particle moves away, v <= 0) the law takes its values at v_min, so g is continuous and a
grazing happens at |w| = D(v_min), as (8)'s at |w| = 1. Above v_max the law is not known: the run
stops with a status.

Every crossing of g starts inside the band ``lo <= |w|``, lo the least clearance over the measured
speeds, so the certified search of :mod:`slosh_bif.flows.impact.flow` runs with the threshold lo
instead of 1, and inside the band (:func:`band`) the flow steps by the propagator of a fixed
dyadic level, testing g at each step's end; a crossing found is solved by bisection on the flow's
Taylor series. A crossing that enters and leaves the wall within one step (a penetration below
``|w''| L**2 / 8``, L the band's step) is not seen: the band is exact up to such grazes.
"""

from __future__ import annotations

import math

import numpy as np

from slosh_bif.flows.compiled import jit
from slosh_bif.flows.impact.crossings import apply, carry, flow_taylor

__all__ = [
    "BAND_LEVEL",
    "law",
    "wall_gap",
    "advance",
    "band",
    "law_arrays",
    "inside_measured_wall",
    "within_measured_band",
]

BAND_LEVEL = 5  # the band's step: the sample step / 32
# Codes of a band march.
REACHED, LEFT, HIT, TOO_FAST = 0, 1, 2, 3


def law_arrays(wall):
    """The compiled law's inputs from a :class:`~slosh_bif.model.restitution.wall.WallLaw`:
    (off, scale) of the log-speed window, the stacked series (kappa, its slope, log D, its slope),
    (v_min, v_max) and the band's threshold lo (the least D over the speeds, less 1e-9)."""
    (off, scale), stacked, _ = wall._coefficients
    grid = np.geomspace(wall.v_min, wall.v_max, 4001)
    lo = float(np.min(wall.clearance(grid))) * (1.0 - 1e-9)
    return np.array([off, scale, wall.v_min, wall.v_max, lo]), np.ascontiguousarray(stacked)


def inside_measured_wall(wall, y) -> float:
    """D(v) - |w| at state y (>= 0 inside): v the speed towards the nearer wall, clamped to the
    law's speeds as the compiled flow clamps it."""
    v = min(max(float(np.sign(y[2]) * y[3]), wall.v_min), wall.v_max)
    return float(wall.clearance(v)) - abs(float(y[2]))


def within_measured_band(wall, y) -> bool:
    """Whether the particle at state y lies within the band a rebound can leave it in (|w| up to
    the highest clearance over the measured speeds), whatever g says: a flight that left the wall
    beyond D(v_min) starts where g, read at v_min for a particle moving away, counts it inside the
    wall, and one that turns back before leaving the band (a soft wall's two impacts on one side)
    approaches from there; the flow carries such states on as its own."""
    return abs(float(y[2])) <= wall.highest_clearance


@jit(inline=True)
def law(shape, stacked, v):
    """(kappa, d kappa/dv, D, dD/dv) at speed v, clamped below at v_min (slopes 0 there): the
    Chebyshev series in log v by the three-term recurrence."""
    slope = 1.0
    if v <= shape[2]:
        v, slope = shape[2], 0.0
    x = min(max(shape[0] + shape[1] * math.log(v), -1.0), 1.0)
    k = dk = ld = dld = 0.0
    t0, t1 = 1.0, x
    for i in range(stacked.shape[0]):
        t = t0 if i == 0 else t1
        if i >= 2:
            t = 2.0 * x * t1 - t0
            t0, t1 = t1, t
        k += t * stacked[i, 0]
        dk += t * stacked[i, 1]
        ld += t * stacked[i, 2]
        dld += t * stacked[i, 3]
    clearance = math.exp(ld)
    return k, slope * dk / v, clearance, slope * clearance * dld / v


@jit(inline=True)
def wall_gap(shape, stacked, z):
    """g = |w| - D(v) on the particle's side, v its speed towards that wall (> 0 beyond the wall)."""
    side = 1.0 if z[2] >= 0.0 else -1.0
    v = min(side * z[3], shape[3])
    return side * z[2] - law(shape, stacked, v)[2]


@jit
def advance(flights, level, s, z, variations, tmp, zb):
    """Advance z (and with ``jac`` the variations) by s < lengths[level - 1], as the binary
    expansion of s over the levels from ``level`` on (exact to the finest level's length); the
    records as in :func:`~slosh_bif.flows.impact.crossings.piece`."""
    table, dtable, _, _, _, lengths, _, _ = flights
    jac, phi, dp = variations
    for k in range(level, lengths.shape[0] - 1):
        if s >= lengths[k] * (1.0 - 1e-12):
            apply(table[k], z, zb)
            if jac:
                carry(table[k], dtable[k], z, phi, dp, tmp)
            z[:] = zb
            s -= lengths[k]


@jit
def band(flights, wall, z, rest, work, variations):
    """March z through the band |w| >= lo for at most ``rest``: returns (code, elapsed) with code
    REACHED (``rest`` used up), LEFT (|w| < lo again) or HIT (z is the state at the wall, before
    the reset; TOO_FAST when the impact speed is above v_max). ``wall = (shape, stacked)`` is the
    measured law of :func:`law_arrays`; the other records as in
    :func:`~slosh_bif.flows.impact.crossings.piece`."""
    table, dtable, K, _, taylor, lengths, _, _ = flights
    shape, stacked = wall
    _, _, _, tmp, za, zb = work
    jac, phi, dp = variations
    L = lengths[BAND_LEVEL]
    elapsed = 0.0
    lo = shape[4]
    while True:
        if rest - elapsed <= lengths[lengths.shape[0] - 2]:
            return REACHED, elapsed
        full = rest - elapsed >= L
        step = L if full else rest - elapsed
        if full:
            apply(table[BAND_LEVEL], z, zb)
        else:
            flow_taylor(K, taylor, z, step, zb)
        if wall_gap(shape, stacked, z) < 0.0 <= wall_gap(shape, stacked, zb):
            a, b = 0.0, step  # g(a) < 0 <= g(b): bisection to rounding on the Taylor flow
            for _ in range(80):
                m = 0.5 * (a + b)
                if m <= a or m >= b:
                    break
                flow_taylor(K, taylor, z, m, za)
                if wall_gap(shape, stacked, za) < 0.0:
                    a = m
                else:
                    b = m
            advance(flights, BAND_LEVEL + 1, b, z, variations, tmp, zb)
            side = 1.0 if z[2] >= 0.0 else -1.0
            return (TOO_FAST if side * z[3] > shape[3] else HIT), elapsed + b
        if full:
            if jac:
                carry(table[BAND_LEVEL], dtable[BAND_LEVEL], z, phi, dp, tmp)
            z[:] = zb
        else:
            advance(flights, BAND_LEVEL + 1, step, z, variations, tmp, zb)
        elapsed += step
        if abs(z[2]) < lo:
            return LEFT, elapsed
