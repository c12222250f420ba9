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

The normal-form coefficients of an orbit's bifurcations need the map's second and third
derivatives, and through the impact those of the reset in the velocity before it:
:func:`reset_jet` gives ``w'+`` and its first three derivatives in ``w'-`` (dL/dw'- = q L / w'-
for L = c v**q with v = side * w'-, and so on), for the jets that carry the map's derivatives
through each impact (:mod:`slosh_bif.orbits.impact.map_derivatives`).

The corrected impact model is (9) with its wall replaced by the wall's own measured law: it flies
on (9)'s linear part (the exact coefficients, not (8)'s first-order ones), and impacts with the
restitution kappa_wall(v) at the clearance ``|w| = D(v)`` of the equivalent rigid wall
(:mod:`slosh_bif.model.restitution.wall`), a surface that depends on the impact speed:
``h(y) = side * w - D(side * w')``, whose gradient has a component ``-side D'(v)`` along w'. Its
kernel (:func:`measured_saltation`) takes kappa, d kappa/dv and dD/dv at the impact speed.
"""

from __future__ import annotations

import models as m
import sympy as sp

side, loss, q = sp.symbols("side loss q", real=True)
kappa, dkappa, dclear = sp.symbols("kappa dkappa dclear", real=True)
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
    S = _saltation_matrix(G, f_minus, f_plus, normal)
    return S, w_plus, sp.diff(w_plus, loss)


def reset_jet():
    """[w'+, d w'+/d w'-, d2, d3] at an impact of (8) with loss ``loss`` = L(v) = c v**q: the
    derivatives of L in w'- written as q (q - 1) ... L / w'-**k (L is a power of v = side w'-), and
    checked against the reset differentiated with L = c (side w'-)**q itself, on both walls."""
    wd = m.STATE[3]
    L = sp.Function("L")
    w_plus = -sp.sqrt(1 - L(wd)) * wd
    jet = []
    for k in range(4):
        expr = sp.diff(w_plus, wd, k)
        for j in range(k, 0, -1):  # highest derivative first, so that lower ones are not mistaken
            expr = expr.subs(sp.Derivative(L(wd), (wd, j)), sp.ff(q, j) * loss / wd**j)
        jet.append(sp.factor_terms(sp.simplify(expr.subs(L(wd), loss))))
    c, v = sp.symbols("c v", positive=True)
    for wall in (1, -1):
        direct = -sp.sqrt(1 - c * (wall * wd) ** q) * wd
        at = {wd: wall * v, loss: c * v**q}
        for k, expr in enumerate(jet):
            gap = sp.simplify(sp.diff(direct, wd, k).subs(wd, wall * v) - expr.subs(at))
            if gap != 0:
                raise AssertionError(f"the reset's derivative {k} differs from its direct form: {gap}")
    return sp.Matrix(jet)


def measured_saltation():
    """(S, w'+) for an impact of the corrected impact model on the wall ``side`` at ``|w| = D(v)``
    with restitution kappa(v), given kappa, dkappa = kappa'(v) and dclear = D'(v)."""
    X, Xd, w, wd = m.STATE
    v = side * wd
    K, D = sp.Function("K"), sp.Function("D")

    def given(expr, value):  # a derivative of K or D at v, written as the kernel's input
        return expr.replace(lambda e: isinstance(e, (sp.Subs, sp.Derivative)), lambda e: value)

    w_plus_of_v = -K(v) * wd
    G = sp.eye(4)
    G[3, 3] = given(sp.diff(w_plus_of_v, wd), dkappa).subs(K(v), kappa)
    w_plus = w_plus_of_v.subs(K(v), kappa)
    after = dict(zip(m.STATE, (X, Xd, w, w_plus)))
    f_minus = m.flight_rhs()
    f_plus = f_minus.subs(after, simultaneous=True)
    normal = sp.Matrix([[given(sp.diff(side * w - D(v), u), dclear) for u in m.STATE]])
    S = _saltation_matrix(G, f_minus, f_plus, normal, simplify=sp.cancel)
    return S, w_plus


def _saltation_matrix(G, f_minus, f_plus, normal, simplify=sp.simplify):
    """S from its formula, each entry simplified (``sp.cancel`` for the measured wall's, whose
    entries full simplification takes half a minute over) and its defining properties checked."""
    S = G + (f_plus - G * f_minus) * normal / (normal * f_minus)[0]
    S = S.applyfunc(lambda e: sp.factor_terms(simplify(e)))
    _check(S, G, f_minus, f_plus, normal)
    return S


def _check(S, G, f_minus, f_plus, normal):
    """S f- = f+ and S u = G u for u tangent to the wall (side**2 = 1 on the wall)."""
    on_wall = {side**2: 1}
    gap = (S * f_minus - f_plus).applyfunc(lambda e: sp.simplify(e.subs(on_wall)))
    if gap != sp.zeros(4, 1):
        raise AssertionError(f"the saltation matrix does not map f- to f+: {gap.T}")
    tangents = sp.Matrix.hstack(*(normal.T.nullspace()))
    for u in (tangents[:, j] for j in range(tangents.shape[1])):
        if sp.simplify((normal * u)[0].subs(on_wall)) != 0:
            raise AssertionError(f"{u.T} is not tangent to the wall")
        if (S * u - G * u).applyfunc(sp.simplify) != sp.zeros(4, 1):
            raise AssertionError(f"the saltation matrix is not G on the wall's tangent {u.T}")


def kernel_functions(Function):
    """The compiled flow's impact kernels: (21)'s, out = [S row-major (16), w'+, dw'+/dL], the
    measured wall's, out = [S row-major (16), w'+], and (21)'s reset with its derivatives."""
    S, w_plus, dloss = saltation()
    measured, measured_w_plus = measured_saltation()
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
        ),
        Function(
            "impact_measured_kernel",
            "out = [S (16, row-major), w'+] of an impact of the corrected impact model on the wall "
            "side (eqs. 2, 8; the wall at |w| = D(v) with restitution kappa(v) of the measured wall); "
            "y is the state before it, pars = (eps, beta, gamma, sigma, Abar, side, kappa, "
            "kappa'(v), D'(v)).",
            (("y", m.STATE),),
            (m.eps, m.beta, m.gamma, m.sigma, m.Abar, side, kappa, dkappa, dclear),
            sp.Matrix(list(measured) + [measured_w_plus]),
        ),
        Function(
            "impact_reset_jet_kernel",
            "out = [w'+, dw'+/dw'-, d2 w'+/dw'-2, d3 w'+/dw'-3] of an impact of (8) on either wall "
            "(eqs. 2, 21); y is the state before it, pars = (loss, q).",
            (("y", m.STATE),),
            (loss, q),
            reset_jet(),
        ),
    ]
