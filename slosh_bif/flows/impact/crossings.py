"""Impacts of (8) found with a certificate (the paragraph of :mod:`slosh_bif.flows.impact.flow`):
an interval of a flight is free of the wall when both parabolas bounding w from its ends stay below
it; an interval holding exactly one crossing is solved by Newton on the flow's Taylor series (the
Jacobian carried to it by the same series); the saltation matrix of an impact (derived by sympy)
maps the flow's Jacobian across it (eqs. 2, 8, 21)."""

from __future__ import annotations

import numpy as np

from slosh_bif.flows.compiled import jit

__all__ = [
    "LEVELS",
    "apply",
    "carry",
    "carry_taylor",
    "crossing",
    "flow_taylor",
    "max_abs",
    "may_reach",
    "piece",
    "saltation",
    "sticks",
]

LEVELS = 48  # the finest interval is h 2**-48
ON_WALL = 1.0 + 4 * 2.0**-52  # f at most this is on the wall or inside it, to rounding
STICK_RISE = 1e-12
"""A flight that rises less than this from the wall before the push brings it back is not
resolved: w is known to rounding (2.2e-16 at |w| = 1), and below this rise the next impact's
instant and speed carry rounding of the order of the flight itself (a chattering sequence then
settles into a spurious one at a fixed tiny speed instead of accumulating). It counts as sticking."""


@jit(inline=True)
def may_reach(f0, d0, f1, d1, L, B):
    """Whether f may reach 1 in (0, L]: f(0) = f0 <= 1 (1 only when leaving the wall, d0 < 0),
    f(L) = f1, slopes d0, d1, |f''| <= B."""
    if d0 < 0.0 and d1 < 0.0 and -(d0 + d1) > B * L and f0 <= ON_WALL:
        # f' <= min(d0 + B s, d1 + B (L - s)) < 0 throughout: f falls from f(0), so it cannot
        # come back to the wall, whatever rounding makes of f(L) (a particle leaving at speed v
        # stays within w's rounding of the wall for about 1e-16 / v of tau, which halving to the
        # finest intervals would walk through one by one)
        return False
    if f1 >= 1.0 or (f0 >= 1.0 and d0 >= 0.0):
        return True
    denom = d0 - d1 + B * L  # >= 0, as |d1 - d0| <= B L
    if denom <= 0.0:
        return max(f0, f1) + 0.125 * B * L * L >= 1.0  # the linear interpolant's bound
    s = -(f0 - f1 + d1 * L - 0.5 * B * L * L) / denom  # where the two parabolas meet
    if s <= 0.0 or s >= L:
        return False  # the envelope is one convex parabola, below 1 at s = L and at most 1 at s = 0
    return f0 + d0 * s + 0.5 * B * s * s >= 1.0


@jit(inline=True)
def sticks(K, z, side, stick_speed):
    """Whether the particle, just leaving the wall ``side`` at the state z, stays on it: its speed
    below ``stick_speed``, or pushed back onto the wall (``side * w'' > 0``, w'' from K's fourth
    row) within a rise ``w'**2 / (2 side w'')`` below :data:`STICK_RISE`."""
    v = z[3]
    if abs(v) < stick_speed:
        return True
    push = 0.0
    for m in range(6):
        push += K[3, m] * z[m]
    push *= side
    return push > 0.0 and v * v < 2.0 * push * STICK_RISE


@jit(inline=True)
def max_abs(z):
    m = 0.0
    for i in range(6):
        m = max(m, abs(z[i]))
    return m


@jit(inline=True)
def flow_taylor(K, terms, z, s, out):
    """``out = expm(K s) z`` by its Taylor series in Horner form (``terms`` terms: exact to
    rounding for s up to the sample step)."""
    acc = np.empty(6)
    acc[:] = z
    for j in range(terms, 0, -1):
        for i in range(6):
            v = 0.0
            for m in range(6):
                v += K[i, m] * acc[m]
            out[i] = z[i] + v * s / j
        acc[:] = out


@jit
def crossing(K, terms, za, side, L, out, c):
    """The one s in (0, L] where ``side * w = c``, with f = side * w - c increasing over [0, L] and
    f(0) < 0 <= f(L): Newton on the Taylor-series flow from za, kept inside the bracket (bisection
    where a Newton step leaves it); ``out`` is the state there (the caller puts w on the wall)."""
    a, b = 0.0, L
    s = 0.5 * L
    for _ in range(200):
        flow_taylor(K, terms, za, s, out)
        f = side * out[2] - c
        if f == 0.0:
            return s
        if f > 0.0:
            b = s
        else:
            a = s
        slope = side * out[3]
        nxt = s - f / slope if slope > 0.0 else 0.5 * (a + b)
        if not (a <= nxt <= b):
            nxt = 0.5 * (a + b)
        if abs(nxt - s) <= 2e-16 * s or b - a <= 2e-16 * b:
            break
        s = nxt
    flow_taylor(K, terms, za, nxt, out)
    return nxt


@jit(inline=True)
def saltation(S, phi, dp):
    """``phi <- S phi``, ``dp <- S dp`` across an impact: S (row-major, 16) is the saltation matrix
    of the reset (2), (21), written by the sympy derivation (``derivations/impact_reset.py``)."""
    col = np.empty(4)
    for j in range(phi.shape[1] + 1):
        for i in range(4):
            acc = 0.0
            for m in range(4):
                acc += S[4 * i + m] * (phi[m, j] if j < phi.shape[1] else dp[m])
            col[i] = acc
        if j < phi.shape[1]:
            phi[:, j] = col
        else:
            dp[:] = col


@jit(inline=True)
def apply(P, z, out):
    """``out = P z`` (6 x 6)."""
    for i in range(6):
        acc = 0.0
        for j in range(6):
            acc += P[i, j] * z[j]
        out[i] = acc


@jit(inline=True)
def carry(P, Q, za, phi, dp, tmp):
    """The variations over an interval of propagator P from state za: ``phi <- A phi`` and
    ``dp <- A dp + Q za`` (A the top-left 4 x 4 block of P; Q the parameter derivative of P)."""
    for i in range(4):
        for j in range(4):
            acc = 0.0
            for m in range(4):
                acc += P[i, m] * phi[m, j]
            tmp[i, j] = acc
    for i in range(4):
        acc = 0.0
        for m in range(4):
            acc += P[i, m] * dp[m]
        for m in range(6):
            acc += Q[i, m] * za[m]
        tmp[i, 4] = acc
    phi[:, :] = tmp[:, :4]
    dp[:] = tmp[:, 4]


@jit(inline=True)
def carry_taylor(K, Kp, terms, za, s, phi, dp, tmp):
    """``carry`` over a length s the tables do not hold (up to a crossing): ``phi <- A(s) phi`` and
    ``dp <- A(s) dp + Q(s) za``, by the Taylor series of the flight on each column of phi and of
    its variational system ``[z, dz]' = [[K, 0], [Kp, K]] [z, dz]`` from ``[za, dp]`` (Horner form;
    two terms beyond the flight's own for the derivative's extra factor k)."""
    v = np.zeros(6)
    out = np.empty(6)
    for j in range(4):
        v[:4] = phi[:, j]
        flow_taylor(K, terms, v, s, out)
        tmp[:, j] = out[:4]
    top = np.empty(6)
    bottom = np.zeros(6)
    bottom[:4] = dp
    top[:] = za
    new_top = np.empty(6)
    new_bottom = np.empty(6)
    for j in range(terms + 2, 0, -1):
        for i in range(6):
            a = 0.0
            b = 0.0
            for m in range(6):
                a += K[i, m] * top[m]
                b += Kp[i, m] * top[m] + K[i, m] * bottom[m]
            new_top[i] = za[i] + a * s / j
            new_bottom[i] = (dp[i] if i < 4 else 0.0) + b * s / j
        top[:] = new_top
        bottom[:] = new_bottom
    phi[:, :] = tmp[:, :4]
    dp[:] = bottom[:4]


@jit
def piece(flights, z, k0, out, work, variations, c):
    """Advance ``z`` over one dyadic piece of length ``lengths[k0]``, or to the first crossing of
    ``|w| = c`` in it (c = 1: an impact of (8)); with ``jac``, carry the variations ``phi``
    (d y / d y0) and ``dp`` (d y / d param) along.

    The records: ``flights = (table, dtable, K, Kp, taylor, lengths, growth, row_norm)``, the
    flights' constants of one parameter set (:class:`~slosh_bif.flows.impact.flow.ImpactFlow`);
    ``work = (stack_z, stack_k, stack_s, tmp, za, zb)``, scratch arrays; ``variations = (jac,
    phi, dp)``.

    Returns ``(side, s)``: side 0 and s the piece's length when it is free (``out`` is the end
    state), or the wall hit (+1/-1) and its offset s (``out`` is the state there, before the reset).
    """
    table, dtable, K, Kp, taylor, lengths, growth, row_norm = flights
    stack_z, stack_k, stack_s, tmp, za, zb = work
    jac, phi, dp = variations
    top = 0
    stack_k[0] = k0
    stack_s[0] = 0.0
    stack_z[0, :] = z
    reached = 0.0
    out[:] = z
    while top >= 0:
        k = stack_k[top]
        s = stack_s[top]
        za[:] = stack_z[top]
        top -= 1
        apply(table[k], za, zb)
        L = lengths[k]
        B = row_norm * growth[k] * max_abs(za) / c
        up = may_reach(za[2] / c, za[3] / c, zb[2] / c, zb[3] / c, L, B)
        down = may_reach(-za[2] / c, -za[3] / c, -zb[2] / c, -zb[3] / c, L, B)
        if not (up or down) or (
            k == LEVELS and (abs(zb[2]) < c or (abs(zb[2]) == c and zb[2] * zb[3] < 0.0))
        ):
            out[:] = zb  # free, or a tangency within rounding, or on the wall (to rounding) moving off it
            reached = s + L
            if jac:
                carry(table[k], dtable[k], za, phi, dp, tmp)
            continue
        if k == LEVELS:
            out[:] = zb
            if jac:
                carry(table[k], dtable[k], za, phi, dp, tmp)
            return (1 if zb[2] >= c else -1), s + L
        if up != down:  # one wall only: a single crossing where f is certified monotone
            side = 1.0 if up else -1.0
            if side * zb[2] >= c and side * za[3] / c - B * L > 0.0:
                offset = crossing(K, taylor, za, side, L, out, c)
                if jac:
                    carry_taylor(K, Kp, taylor, za, offset, phi, dp, tmp)
                return int(side), s + offset
        top += 1  # right half, then left half on top of it
        stack_k[top] = k + 1
        stack_s[top] = s + lengths[k + 1]
        apply(table[k + 1], za, stack_z[top])
        top += 1
        stack_k[top] = k + 1
        stack_s[top] = s
        stack_z[top, :] = za
    return 0, reached
