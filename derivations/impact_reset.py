"""The impact of the vibro-impact model (8): its reset (2), (21) and its saltation matrix.

An impact happens where the particle reaches the wall, ``h(y) = side * w - 1 = 0`` (side = +-1, the
wall hit), moving into it (speed ``v = side * w' > 0``). The reset keeps X, X' and w and reverses
the particle's velocity with the restitution of (21), ``w'+ = -kappa(v) w'-``, ``kappa(v) =
sqrt(1 - L(v))`` where ``L(v) = c v**q`` is the fraction of the kinetic energy the impact takes
(c and q = pbar/(n+1) from (21); q = 0 is the "Newtonian" wall of (40)).

A flow's Jacobian crosses an impact by the saltation matrix

    S = G + (f+ - G f-) n^T / (n^T f-),

with G = dR/dy the reset's Jacobian, n = grad h, and f-+ the vector field of (8) at the states
before and after the impact (the correction for the impact time moving with the initial state).
:func:`saltation` builds S from (8)'s own right-hand side and proves its two defining properties:
S maps f- to f+, and S acts as G on the directions tangent to the wall (n^T u = 0).

The kernel written from it takes the impact's energy loss L = c v**q as an input (the compiled
flow computes it to test for a real kappa first): dL/dv = q L / v, and dL/dc = L / c carries a
wall parameter's derivative (lam, chi move c).
"""

from __future__ import annotations

import models as m
import sympy as sp

side, loss, q = sp.symbols("side loss q", real=True)
tau = m.tau


def _derivative_of_L(expr, v):
    """d/dv L(v) written as q L(v) / v (L = c v**q)."""
    return expr.replace(lambda e: isinstance(e, (sp.Subs, sp.Derivative)), lambda e: q * loss / v)


def saltation():
    """(S, w'+, dw'+/dL) for an impact on the wall ``side`` with loss ``loss``; S is 4 x 4 in y."""
    X, Xd, w, wd = m.STATE
    v = side * wd
    L = sp.Function("L")
    w_plus_of_L = -sp.sqrt(1 - L(v)) * wd
    slope = _derivative_of_L(sp.diff(w_plus_of_L, wd), v).subs(L(v), loss)
    w_plus = w_plus_of_L.subs(L(v), loss)
    G = sp.eye(4)
    G[3, 3] = slope
    after = dict(zip(m.STATE, (X, Xd, w, w_plus)))
    f_minus = m.impact_rhs()
    f_plus = f_minus.subs(after, simultaneous=True)
    normal = sp.Matrix([[0, 0, side, 0]])  # grad (side * w - 1)
    S = G + (f_plus - G * f_minus) * normal / (normal * f_minus)[0]
    S = S.applyfunc(lambda e: sp.factor_terms(sp.simplify(e)))
    _check(S, G, f_minus, f_plus, normal)
    return S, w_plus, sp.diff(w_plus, loss)


def _check(S, G, f_minus, f_plus, normal):
    """S f- = f+ and S u = G u for u tangent to the wall (side**2 = 1 on the wall)."""
    on_wall = {side**2: 1}
    gap = (S * f_minus - f_plus).applyfunc(lambda e: sp.simplify(e.subs(on_wall)))
    if gap != sp.zeros(4, 1):
        raise AssertionError(f"the saltation matrix does not map f- to f+: {gap.T}")
    for u in (sp.Matrix([1, 0, 0, 0]), sp.Matrix([0, 1, 0, 0]), sp.Matrix([0, 0, 0, 1])):
        assert (normal * u)[0] == 0
        if (S * u - G * u).applyfunc(sp.simplify) != sp.zeros(4, 1):
            raise AssertionError(f"the saltation matrix is not G on the wall's tangent {u.T}")


def kernel_functions(Function):
    """The compiled flow's impact kernel: out = [S row-major (16), w'+, dw'+/dL]."""
    S, w_plus, dloss = saltation()
    outputs = sp.Matrix(list(S) + [w_plus, dloss])
    if side in outputs.free_symbols:  # it cancels: one kernel for both walls
        raise AssertionError("the saltation matrix depends on the wall's side")
    return [
        Function(
            "impact_saltation_kernel",
            "out = [S (16, row-major), w'+, dw'+/dloss] of an impact of (8) on either wall "
            "(eqs. 2, 8, 21); y is the state before it, pars = (eps, beta, gamma, sigma, Abar, loss, q).",
            (("y", m.STATE),),
            (m.eps, m.beta, m.gamma, m.sigma, m.Abar, loss, q),
            outputs,
        )
    ]
