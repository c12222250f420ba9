"""Brent's method for a root in a bracket (R. P. Brent, *Algorithms for Minimization without
Derivatives*, 1973, ch. 4): the continuation's special points (LP, BP, PD, NS) are located by it
on the arclength, each trial a corrector solve, and the flights of the impact model (8) end at
roots of the gap.

In the package rather than from scipy.optimize, whose import (about 0.1 s: sparse linear algebra,
linear programming) every shooting run with a special point would otherwise pay. The convergence
rule is scipy's ``brentq``'s: the root is returned once the bracket is narrower than
``xtol + rtol * |x|``.
"""

from __future__ import annotations

import math

__all__ = ["brent", "MIN_RTOL"]

MIN_RTOL = 4 * 2.220446049250313e-16
"""The smallest relative tolerance accepted, four units of rounding (as scipy's brentq)."""


def brent(
    f,
    a: float,
    b: float,
    *,
    xtol: float = 2e-12,
    rtol: float = MIN_RTOL,
    maxiter: int = 100,
    fa: float | None = None,
    fb: float | None = None,
) -> float:
    """A root of ``f`` in [a, b], where f(a) and f(b) differ in sign (or one is zero); ``fa``,
    ``fb``: f(a) and f(b) where the caller has them (each evaluation may be a corrector solve).

    Each step takes inverse quadratic interpolation or the secant where it stays well inside the
    bracket and shrinks it fast enough, and bisection otherwise, so the bracket shrinks at worst
    as bisection's. Raises ValueError for a bracket without a sign change or tolerances out of
    range, RuntimeError after ``maxiter`` evaluations without convergence; an exception of ``f``
    passes through.
    """
    if not xtol > 0:
        raise ValueError(f"xtol must be positive; got {xtol}")
    if not rtol >= MIN_RTOL:
        raise ValueError(f"rtol must be at least {MIN_RTOL:.3g}; got {rtol}")
    fa = f(a) if fa is None else fa
    fb = f(b) if fb is None else fb
    if fa == 0:
        return a
    if fb == 0:
        return b
    if math.copysign(1.0, fa) == math.copysign(1.0, fb):
        raise ValueError(f"f({a}) = {fa:.3g} and f({b}) = {fb:.3g} have the same sign: no bracket")
    c, fc = a, fa  # b the best point, c the other end of the bracket, a the previous b
    d = e = b - a
    for _ in range(maxiter):
        if abs(fc) < abs(fb):  # b the end with the smaller residual
            a, fa = b, fb
            b, fb = c, fc
            c, fc = a, fa
        tol = 0.5 * (xtol + rtol * abs(b))
        half = 0.5 * (c - b)
        if abs(half) <= tol or fb == 0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):  # try interpolation
            s = fb / fa
            if a == c:  # two points: the secant
                p, q = 2 * half * s, 1 - s
            else:  # three: inverse quadratic interpolation
                q, r = fa / fc, fb / fc
                p = s * (2 * half * q * (q - r) - (b - a) * (r - 1))
                q = (q - 1) * (r - 1) * (s - 1)
            if p > 0:
                q = -q
            p = abs(p)
            if 2 * p < min(3 * half * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = half
        else:
            d = e = half
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, half)
        fb = f(b)
        if math.copysign(1.0, fb) == math.copysign(1.0, fc) and fb != 0:  # keep [b, c] a bracket
            c, fc = a, fa
            d = e = b - a
    raise RuntimeError(f"Brent's method did not converge in {maxiter} evaluations")
