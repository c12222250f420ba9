"""Multiple-scales derivation of the slow flow of the vibro-impact model (8), the paper's section 3.

Read top to bottom; each step is a function returning sympy objects, and each checks itself with
an assertion where the paper's argument allows it.

1. :func:`expansion` - (22) substituted into (8): the O(1) equations (24) and the O(eps)
   X-equation (41)/(44).
2. :func:`fast_solution` - X0 = A sin(T0 + psi) solves (24a); the w0-part driven by X0 is in
   phase with it and of the same amplitude (C = A), which leaves the impact part f of (26), (29).
3. :func:`triangle_fourier` - the Fourier series (42) of f = (2 alpha/pi) arcsin(cos(T0 - eta)),
   its coefficients integrated by sympy.
4. :func:`impact_conditions` - the wall condition (32) and the restitution jump (30)-(31) at
   T0 = eta, their mirror (33) at the other wall, and the manifold (36): both branches, A_min,
   alpha_min.
5. :func:`slow_flow` - removal of the secular terms of (44): the forced slow flow (45), and the
   free flow (43) as its Abar = 0, sigma = 0 case.
6. :func:`steady_state` - the steady states (46) and the slow-flow Jacobian.
7. :func:`manifold_kappa` - kappa on the manifold (39): the impact speed (38) fed to (21).
8. The corrected slow flow (issue 20): steps 4-6 with the wall at |w| = D instead of 1 (D, the
   clearance the smooth wall of (9) lets the particle use, and kappa both measured per impact
   speed by :mod:`slosh_bif.model.restitution.wall`); :func:`corrected_reduces_to_46` checks that D = 1
   gives (45), (46) back, and that kappa from (21) gives (39) back.

Symbols: ``phase`` is eta + psi, the phase of X0 at an impact on the wall w = +1.
"""

from __future__ import annotations

import functools

import models as m
import sympy as sp

T0, T1 = sp.symbols("T0 T1", real=True)
A, psi, alpha, eta, phase = sp.symbols("A psi alpha eta phase", real=True)
rho, kappa = sp.symbols("rho kappa", positive=True)
theta = sp.Symbol("theta", real=True)
k = sp.Symbol("k", integer=True, positive=True)
dA, dpsi = sp.symbols("dA dpsi", real=True)  # D1 A and D1 psi
drho = sp.Symbol("drho", real=True)  # d rho / dA along the manifold (0 for pbar = 0)
eps, beta, gamma, sigma, Abar, lam, chi = m.eps, m.beta, m.gamma, m.sigma, m.Abar, m.lam, m.chi
n = sp.Symbol("n", positive=True, integer=True)
pbar = sp.Symbol("pbar", integer=True)
v0 = sp.Symbol("v0", positive=True)
delta1, expo = sp.symbols("delta1 expo", real=True)  # delta at unit speed and pbar/(n+1) of (21)
D = sp.Symbol("D", positive=True)  # the clearance: the wall at |w| = D (D = 1 in the paper)
dD = sp.Symbol("dD", real=True)  # d D / dA along the manifold
ONE = sp.Integer(1)


@functools.cache
def expansion():
    """(22) in (8): returns the O(1) X- and w-equations (without impacts) and the O(eps) X-equation."""
    X0, X1, w0, w1 = (sp.Function(s)(T0, T1) for s in ("X0", "X1", "w0", "w1"))

    def d(e):  # d/dtau = D0 + eps D1
        return sp.diff(e, T0) + eps * sp.diff(e, T1)

    X, w = X0 + eps * X1, w0 + eps * w1
    a, b, c, dd = m.impact_coefficients()
    eq_X = d(d(X)) + a * X + b * w + eps * gamma * d(X) - eps * Abar * sp.cos(T0)
    eq_w = d(d(w)) + c * X + dd * w + eps * gamma * d(X) - eps * Abar * sp.cos(T0)
    order = lambda e, j: sp.expand(e).coeff(eps, j)  # noqa: E731
    o1_X, o1_w, oe_X = order(eq_X, 0), order(eq_w, 0), order(eq_X, 1)
    # (24): D0^2 X0 + X0 = 0 and D0^2 w0 + beta^2 w0 + (1 - beta^2) X0 = (impacts).
    assert sp.simplify(o1_X - (X0.diff(T0, 2) + X0)) == 0
    assert sp.simplify(o1_w - (w0.diff(T0, 2) + beta**2 * w0 + (1 - beta**2) * X0)) == 0
    # (41): D0^2 X1 + X1 = -2 D0 D1 X0 - gamma D0 X0 - (1 - beta^2) w0 (+ sigma X0 + Abar cos T0 when forced).
    rhs_41 = -2 * X0.diff(T0, T1) - gamma * X0.diff(T0) - (1 - beta**2) * w0 + sigma * X0 + Abar * sp.cos(T0)
    assert sp.simplify(oe_X - (X1.diff(T0, 2) + X1 - rhs_41)) == 0
    return {
        "X0": X0,
        "X1": X1,
        "w0": w0,
        "order1_X": o1_X,
        "order1_w": o1_w,
        "order_eps_X": oe_X,
        "rhs_41": rhs_41,
    }


@functools.cache
def fast_solution():
    """X0 = A sin(T0 + psi) and the amplitude C of the w0-part it drives (C = A)."""
    e = expansion()
    X0 = A * sp.sin(T0 + psi)
    assert sp.simplify(e["order1_X"].subs(e["X0"], X0).doit()) == 0
    C = sp.Symbol("C")
    w_driven = C * sp.sin(T0 + psi)
    residual = e["order1_w"].subs({e["w0"]: w_driven, e["X0"]: X0}).doit()
    C_value = sp.solve(sp.simplify(residual / sp.sin(T0 + psi)), C)[0]
    return {"X0": X0, "C": C_value}


@functools.cache
def triangle_fourier():
    """Cosine coefficients a_k of f = (2 alpha/pi) arcsin(cos(theta)), theta = T0 - eta.

    On [0, pi], arcsin(cos theta) = pi/2 - theta (cos theta = sin(pi/2 - theta), and pi/2 - theta
    lies in arcsin's range); f is even and 2pi-periodic, so a_k = (2/pi) int_0^pi f cos(k theta).
    """
    f_half = 2 * alpha / sp.pi * (sp.pi / 2 - theta)
    a_k = sp.simplify(2 / sp.pi * sp.integrate(f_half * sp.cos(k * theta), (theta, 0, sp.pi)))
    # The series must return f(0) = alpha at the impact: sum over odd k of 8/(pi^2 k^2) = 1.
    odd = sp.Symbol("j", integer=True, positive=True)
    total = sp.summation(a_k.subs(k, 2 * odd - 1), (odd, 1, sp.oo))
    assert sp.simplify(total - alpha) == 0
    return {"a_k": a_k, "a_1": a_k.subs(k, 1), "f_half": f_half}


@functools.cache
def impact_conditions(clearance=ONE):
    """(30)-(33) and the manifold (36), with the wall at |w| = ``clearance`` (1 in the paper)."""
    X0 = fast_solution()["X0"]
    slope = 2 * alpha / sp.pi  # |D0 f| on either side of the peak at T0 = eta
    # At T0 = eta: w0 = A sin(eta + psi) + alpha = 1 (32).
    wall = sp.Eq(A * sp.sin(phase) + alpha, clearance)
    # Velocities just before and after: A cos(phase) +/- slope; the law (2): after = -kappa * before.
    before, after = A * sp.cos(phase) + slope, A * sp.cos(phase) - slope
    # (30) is the impulse balance: the jump of D0 f (-2 slope) plus (1 + kappa) * before = 0.
    impulse = sp.Eq(2 * slope - (1 + kappa) * slope, (1 + kappa) * A * sp.cos(phase))
    cos_part = sp.solve(sp.Eq(after, -kappa * before), sp.cos(phase))[0] * A
    rho_expr = sp.simplify(cos_part / alpha)
    assert sp.simplify(sp.solve(impulse, sp.cos(phase))[0] * A - cos_part) == 0
    # The wall w = -1 at T0 = eta + pi: X0 and f both change sign, so (33) repeats (31)-(32).
    assert sp.simplify(X0.subs(T0, eta + sp.pi) + X0.subs(T0, eta)) == 0
    # (36): A^2 = (A cos)^2 + (A sin)^2 = (rho alpha)^2 + (1 - alpha)^2, solved for alpha.
    manifold = sp.Eq(A**2, (rho * alpha) ** 2 + (clearance - alpha) ** 2)
    roots = sp.solve(manifold, alpha)
    disc = sp.discriminant(sp.expand(manifold.rhs - manifold.lhs), alpha)
    a_min = sp.sqrt(sp.solve(sp.Eq(disc, 0), A**2)[0])
    stable = (clearance + sp.sqrt((1 + rho**2) * (A**2 - a_min**2))) / (1 + rho**2)
    unstable = (clearance - sp.sqrt((1 + rho**2) * (A**2 - a_min**2))) / (1 + rho**2)
    for branch in (stable, unstable):
        assert any(sp.simplify(sp.expand(r - branch)) == 0 or _numerically_equal(r, branch) for r in roots)
    return {
        "rho": rho_expr,
        "cos_phase": rho * alpha / A,
        "sin_phase": (clearance - alpha) / A,
        "impulse_30": impulse,
        "wall_32": wall,
        "alpha_stable": stable,
        "alpha_unstable": unstable,
        "A_min": sp.simplify(a_min),
        "alpha_min": sp.simplify(stable.subs(A, a_min)),
        "impact_speed": sp.simplify(before.subs(sp.cos(phase), rho * alpha / A)),
    }


def _numerically_equal(a, b, points=((0.7, 0.3, 1.2), (1.9, 0.05, 1.05), (3.2, 0.6, 1.4))):
    return all(abs(complex((a - b).subs({A: x, rho: r, D: c}).evalf(30))) < 1e-20 for x, r, c in points)


@functools.cache
def slow_flow(clearance=ONE):
    """Secular conditions of (44): D1 A and D1 psi, forced (45) and free (43)."""
    e = expansion()
    X0 = fast_solution()["X0"]
    a_1 = triangle_fourier()["a_1"]
    A_f, psi_f = sp.Function("A")(T1), sp.Function("psi")(T1)
    # Only the first harmonic of f resonates with X1's operator D0^2 + 1.
    w0 = A_f * sp.sin(T0 + psi_f) + a_1 * sp.cos(T0 + psi_f - phase)
    rhs = e["rhs_41"].subs({e["w0"]: w0, e["X0"]: X0.subs({A: A_f, psi: psi_f})}).doit()
    rhs = rhs.subs({sp.Derivative(A_f, T1): dA, sp.Derivative(psi_f, T1): dpsi}).subs({A_f: A, psi_f: psi})
    # Project on cos(T0 + psi) and sin(T0 + psi): with theta = T0 + psi, over one period.
    in_theta = sp.expand(sp.expand_trig(rhs.subs(T0, theta - psi)))
    secular = [
        sp.integrate(in_theta * basis, (theta, 0, 2 * sp.pi)) / sp.pi
        for basis in (sp.cos(theta), sp.sin(theta))
    ]
    solved = sp.solve(secular, [dA, dpsi], dict=True)[0]
    ic = impact_conditions(clearance)
    on_manifold = {sp.cos(phase): ic["cos_phase"], sp.sin(phase): ic["sin_phase"]}
    forced = [sp.simplify(sp.expand(solved[v]).subs(on_manifold)) for v in (dA, dpsi)]
    free = [sp.simplify(f.subs({Abar: 0, sigma: 0})) for f in forced]
    return {"forced": forced, "free": free, "secular": secular}


@functools.cache
def steady_state(clearance=ONE):
    """(46): the residual of the steady states, and its pieces (energy and phase balances)."""
    dA_rhs, dpsi_rhs = slow_flow(clearance)["forced"]
    # Steady state: Abar cos psi and Abar sin psi solve D1 A = D1 psi = 0, then cos^2 + sin^2 = 1.
    cos_psi = sp.solve(dA_rhs, sp.cos(psi))[0] * Abar
    sin_psi = sp.solve(dpsi_rhs, sp.sin(psi))[0] * Abar
    scale = sp.pi**2 * A  # brings (46) to the paper's polynomial form
    energy = sp.expand(scale * cos_psi)
    phase_balance = sp.expand(scale * sin_psi)
    residual = energy**2 + phase_balance**2 - sp.pi**4 * A**2 * Abar**2
    return {
        "residual": residual,
        "energy": energy,
        "phase": phase_balance,
        "cos_psi": cos_psi / Abar,
        "sin_psi": sin_psi / Abar,
    }


@functools.cache
def manifold_kappa():
    """(38)-(39): kappa from (21) at the impact speed alpha (2/pi + rho) on the stable branch."""
    ic = impact_conditions()
    speed = sp.simplify(ic["impact_speed"].subs(rho, ic["rho"]))  # = 4 alpha / (pi (1 + kappa))
    residual = kappa**2 - 1 + delta1 * speed**expo
    return {"speed": speed, "residual": residual}


# --- what the package uses: functions of (A, psi) on the stable branch S+ -----------------------


def _on_stable_branch(expr, clearance=ONE):
    return expr.subs(alpha, impact_conditions(clearance)["alpha_stable"])


def _at_manifold_end(expr, clearance=ONE):
    """An expression on the manifold's end (36): alpha = alpha_min, A = A_min (both in rho), so that
    evaluating it there meets no square root of a rounding-negative number."""
    ic = impact_conditions(clearance)
    return sp.simplify(expr.subs(alpha, ic["alpha_min"]).subs(A, ic["A_min"]))


def _total_dA(expr):
    """d/dA of an expression in A, rho and D, with rho = rho(A) and D = D(A) along the manifold
    (slopes drho and dD)."""
    R, C = sp.Function("R")(A), sp.Function("C")(A)
    total = sp.diff(expr.subs({rho: R, D: C}), A)
    return total.subs({sp.Derivative(R, A): drho, sp.Derivative(C, A): dD}).subs({R: rho, C: D})


def generated_functions(Function):
    """The slow-flow functions written to slosh_bif/model/_generated/slow_flow.py."""
    ic, ss, mk = impact_conditions(), steady_state(), manifold_kappa()
    rhs = sp.Matrix([_on_stable_branch(e) for e in slow_flow()["forced"]])
    jac = sp.Matrix([[_total_dA(e), sp.diff(e, psi)] for e in rhs])
    residual = _on_stable_branch(ss["residual"])
    balances = sp.Matrix([_on_stable_branch(ss["energy"]), _on_stable_branch(ss["phase"])])
    A_only = ("A", "rho", "kappa")
    slow = (beta, gamma, sigma, Abar)
    return [
        Function(
            "sim_alpha",
            "alpha on the stable branch S+ of the manifold, eq. (36).",
            (),
            (A, rho),
            sp.Matrix([ic["alpha_stable"]]),
            A_only,
        ),
        Function(
            "sim_alpha_unstable",
            "alpha on the unstable branch of the manifold, eq. (36).",
            (),
            (A, rho),
            sp.Matrix([ic["alpha_unstable"]]),
            A_only,
        ),
        Function(
            "sim_a_min", "End A_min of the manifold, eq. (36).", (), (rho,), sp.Matrix([ic["A_min"]]), A_only
        ),
        Function(
            "sim_alpha_min",
            "alpha at the manifold's end, eq. (36).",
            (),
            (rho,),
            sp.Matrix([ic["alpha_min"]]),
            A_only,
        ),
        Function(
            "slow_rhs",
            "Forced slow flow (45) on S+: [D1 A, D1 psi].",
            (),
            (A, psi, rho) + slow,
            rhs,
            ("A", "psi"),
        ),
        Function(
            "slow_jac",
            "Jacobian of (45) in (A, psi); rho = rho(A) with slope drho.",
            (),
            (A, psi, rho, drho) + slow,
            jac,
            ("A", "psi"),
        ),
        Function(
            "slow_dparams",
            "Derivatives of (45) in the parameters: columns d/dsigma, d/dAbar.",
            (),
            (A, psi, rho) + slow,
            sp.Matrix([[sp.diff(e, sigma), sp.diff(e, Abar)] for e in rhs]),
            ("A", "psi"),
        ),
        Function(
            "steady_residual",
            "Steady-state residual (46) on S+ (derived sign).",
            (),
            (A, rho) + slow,
            sp.Matrix([residual]),
            A_only,
        ),
        Function(
            "steady_residual_grad",
            "[dR/dA, dR/dsigma, dR/dAbar] of (46); rho = rho(A) with slope drho.",
            (),
            (A, rho, drho) + slow,
            sp.Matrix([_total_dA(residual), sp.diff(residual, sigma), sp.diff(residual, Abar)]),
            A_only,
        ),
        Function(
            "steady_balances",
            "[pi^2 A Abar cos psi, pi^2 A Abar sin psi] at a steady state of (45).",
            (),
            (A, rho) + slow,
            balances,
            A_only,
        ),
        Function(
            "slow_rhs_end",
            "Forced slow flow (45) at the manifold's end (36), A = A_min, alpha = alpha_min: [D1 A, D1 psi].",
            (),
            (psi, rho) + slow,
            sp.Matrix([_at_manifold_end(e) for e in slow_flow()["forced"]]),
            ("psi",),
        ),
        Function(
            "slow_end_jac",
            "Derivatives of (45) at the manifold's end in psi, sigma and Abar (rows D1 A, D1 psi).",
            (),
            (psi, rho) + slow,
            sp.Matrix(
                [[sp.diff(_at_manifold_end(e), v) for v in (psi, sigma, Abar)] for e in slow_flow()["forced"]]
            ),
            ("psi",),
        ),
        Function(
            "steady_residual_end",
            "[R, dR/dsigma, dR/dAbar] of (46) at the manifold's end (36), A = A_min, alpha = alpha_min.",
            (),
            (rho,) + slow,
            sp.Matrix(
                [
                    _at_manifold_end(ss["residual"]),
                    sp.diff(_at_manifold_end(ss["residual"]), sigma),
                    sp.diff(_at_manifold_end(ss["residual"]), Abar),
                ]
            ),
            ("rho",),
        ),
        Function(
            "manifold_kappa_residual",
            "kappa^2 - 1 + delta1 v^expo with v the impact speed (38), eq. (39).",
            (),
            (kappa, A, delta1, expo),
            sp.Matrix([_on_stable_branch(mk["residual"]).subs(rho, ic["rho"])]),
            A_only,
        ),
        Function(
            "manifold_kappa_residual_grad",
            "[d/dkappa, d/dA] of the residual of eq. (39).",
            (),
            (kappa, A, delta1, expo),
            sp.Matrix(
                [
                    sp.diff(e, v)
                    for e in [_on_stable_branch(mk["residual"]).subs(rho, ic["rho"])]
                    for v in (kappa, A)
                ]
            ),
            A_only,
        ),
    ]


# --- the corrected slow flow (issue 20): the wall at |w| = D, kappa and D from the measured wall --


@functools.cache
def corrected_impact_speed():
    """The impact speed (38) on S+ with the wall at |w| = D, as a function of (A, kappa, D):
    4 alpha_S+(A, rho(kappa), D) / (pi (1 + kappa)). kappa and D are the wall's at this speed,
    which makes it a fixed point in the speed (solved numerically, slosh_bif.model.restitution.corrected)."""
    ic = impact_conditions(D)
    speed = sp.simplify(ic["impact_speed"].subs(rho, ic["rho"]))
    assert sp.simplify(speed - 4 * alpha / (sp.pi * (1 + kappa))) == 0
    on_branch = _on_stable_branch(speed, D).subs(rho, ic["rho"])
    at_end = speed.subs(alpha, ic["alpha_min"]).subs(rho, ic["rho"])
    return {"speed": on_branch, "speed_at_end": sp.simplify(at_end)}


def corrected_reduces_to_46():
    """The corrected equations at D = 1 are (36), (45), (46) as derived; with kappa from (21) the
    fixed point in the impact speed is eq. (39). Raises AssertionError otherwise."""
    for key in ("alpha_stable", "A_min", "alpha_min", "sin_phase"):
        assert sp.simplify(impact_conditions(D)[key].subs(D, 1) - impact_conditions()[key]) == 0, key
    for corrected, paper in zip(slow_flow(D)["forced"], slow_flow()["forced"]):
        assert sp.simplify(corrected.subs(D, 1) - paper) == 0
    assert sp.simplify(steady_state(D)["residual"].subs(D, 1) - steady_state()["residual"]) == 0
    v = corrected_impact_speed()["speed"].subs(D, 1)
    eq39 = _on_stable_branch(manifold_kappa()["residual"]).subs(rho, impact_conditions()["rho"])
    assert sp.simplify((kappa**2 - 1 + delta1 * v**expo) - eq39) == 0
    return True


def corrected_functions(Function):
    """The corrected slow-flow functions: the same as :func:`generated_functions`' with the
    clearance D (and its slope dD along S+) among the arguments, and the impact speed."""
    corrected_reduces_to_46()
    ic, ss, speed = impact_conditions(D), steady_state(D), corrected_impact_speed()
    forced = slow_flow(D)["forced"]
    rhs = sp.Matrix([_on_stable_branch(e, D) for e in forced])
    residual = _on_stable_branch(ss["residual"], D)
    slow = (beta, gamma, sigma, Abar)
    names = ("A", "rho", "kappa", "D")
    end = [_at_manifold_end(e, D) for e in forced]
    end_residual = _at_manifold_end(ss["residual"], D)
    return [
        Function(
            "corrected_alpha",
            "alpha on S+ with the wall at |w| = D, eq. (36) with clearance D.",
            (),
            (A, rho, D),
            sp.Matrix([ic["alpha_stable"]]),
            names,
        ),
        Function(
            "corrected_alpha_unstable",
            "alpha on the unstable branch with the wall at |w| = D.",
            (),
            (A, rho, D),
            sp.Matrix([ic["alpha_unstable"]]),
            names,
        ),
        Function(
            "corrected_a_min",
            "End A_min = D rho / sqrt(1 + rho^2) of the manifold with clearance D.",
            (),
            (rho, D),
            sp.Matrix([ic["A_min"]]),
            names,
        ),
        Function(
            "corrected_slow_rhs",
            "Slow flow (45) on S+ with clearance D: [D1 A, D1 psi].",
            (),
            (A, psi, rho, D) + slow,
            rhs,
            ("A", "psi"),
        ),
        Function(
            "corrected_slow_jac",
            "Jacobian of the corrected (45) in (A, psi); rho(A), D(A) with slopes drho, dD.",
            (),
            (A, psi, rho, drho, D, dD) + slow,
            sp.Matrix([[_total_dA(e), sp.diff(e, psi)] for e in rhs]),
            ("A", "psi"),
        ),
        Function(
            "corrected_slow_dparams",
            "Derivatives of the corrected (45) in sigma and Abar (columns).",
            (),
            (A, psi, rho, D) + slow,
            sp.Matrix([[sp.diff(e, sigma), sp.diff(e, Abar)] for e in rhs]),
            ("A", "psi"),
        ),
        Function(
            "corrected_steady_residual",
            "Steady-state residual (46) with clearance D.",
            (),
            (A, rho, D) + slow,
            sp.Matrix([residual]),
            names,
        ),
        Function(
            "corrected_steady_residual_grad",
            "[dR/dA, dR/dsigma, dR/dAbar] of the corrected (46); slopes drho, dD.",
            (),
            (A, rho, drho, D, dD) + slow,
            sp.Matrix([_total_dA(residual), sp.diff(residual, sigma), sp.diff(residual, Abar)]),
            names,
        ),
        Function(
            "corrected_steady_balances",
            "[pi^2 A Abar cos psi, pi^2 A Abar sin psi] at a steady state of the corrected (45).",
            (),
            (A, rho, D) + slow,
            sp.Matrix([_on_stable_branch(ss["energy"], D), _on_stable_branch(ss["phase"], D)]),
            names,
        ),
        Function(
            "corrected_slow_rhs_end",
            "The corrected (45) at the manifold's end, A = A_min(rho, D): [D1 A, D1 psi].",
            (),
            (psi, rho, D) + slow,
            sp.Matrix(end),
            ("psi",),
        ),
        Function(
            "corrected_slow_end_jac",
            "Derivatives of the corrected (45) at the manifold's end in psi, sigma, Abar.",
            (),
            (psi, rho, D) + slow,
            sp.Matrix([[sp.diff(e, v) for v in (psi, sigma, Abar)] for e in end]),
            ("psi",),
        ),
        Function(
            "corrected_steady_residual_end",
            "[R, dR/dsigma, dR/dAbar] of the corrected (46) at the manifold's end.",
            (),
            (rho, D) + slow,
            sp.Matrix([end_residual, sp.diff(end_residual, sigma), sp.diff(end_residual, Abar)]),
            ("rho",),
        ),
        Function(
            "corrected_impact_speed",
            "[v, dv/dA, dv/dkappa, dv/dD]: the impact speed (38) on S+ with clearance D.",
            (),
            (A, kappa, D),
            sp.Matrix([speed["speed"]] + [sp.diff(speed["speed"], x) for x in (A, kappa, D)]),
            names,
        ),
        Function(
            "corrected_end_speed",
            "[v, dv/dkappa, dv/dD]: the impact speed at the manifold's end (alpha = alpha_min).",
            (),
            (kappa, D),
            sp.Matrix([speed["speed_at_end"]] + [sp.diff(speed["speed_at_end"], x) for x in (kappa, D)]),
            ("kappa",),
        ),
    ]
