"""Integer powers of the wall terms of (9): chi w^(2n+1) and lam w^(2p) w'.

The generated kernels (``_generated/kernels.py``) spell every power with a symbolic exponent as
``int_power(w, 2*n + 1)``. In Python (the scipy fallback) it is ``w ** k``; the compiled
integrator (:mod:`slosh_bif.flows.smooth.dop853`) gives numba its own implementation, repeated
squaring, because libm's ``pow`` sits on the critical path of every Runge-Kutta stage: at
n = 6 and 50 squaring made a period of (9) 28-29 % faster. The two differ in rounding only: a
squaring doubles the relative error it is given, so the result is within k roundings of the exact
power (2e-14 relative at k = 101, far below any tolerance the integrator is given).
"""

from __future__ import annotations

__all__ = ["int_power", "int_power_by_squaring"]


def int_power(x, k):
    """x ** k for an exponent k that is a non-negative whole number stored as a float (n, p of Params)."""
    return x**k


def int_power_by_squaring(x, k):
    """The same power by repeated squaring (the compiled path); ``x ** k`` when k is not a whole
    number >= 0 (never, for admissible Params)."""
    e = int(k)
    if e != k or e < 0:
        return x**k
    result = 1.0
    base = x
    while e:
        if e & 1:
            result *= base
        base *= base
        e >>= 1
    return result
