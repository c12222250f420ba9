"""Symbolic models: the full smooth model (9) and the linear part of the vibro-impact model (8).

State ``y = [X, X', w, w']``, time tau. Model (9) is taken with its exact coefficients

    a = 1 - eps sigma,   b = eps (1 - beta^2)(1 - eps sigma)/(1 + eps beta^2),
    c = (1 - beta^2)(1 - eps sigma)/(1 + eps beta^2),   d = (eps + beta^2)(1 - eps sigma)/(1 + eps beta^2),

    X'' = eps Abar cos(tau) - a X - b w - eps gamma X' - eps^2 gamma w'
    w'' = eps Abar cos(tau) - c X - d w - eps gamma X' - eps^2 gamma w' - lam w' w^(2p) - chi w^(2n+1).

Model (8) is (9) without the wall terms, its coefficients expanded to first order in eps *by sympy*
(the paper's printed (8) has ``eps((1 - beta^2) - sigma beta^2)`` where the expansion gives
``eps(1 - beta^4 - sigma beta^2)``; see REPORT.md). Impacts at |w| = 1 are applied by the
hand-written :mod:`slosh_bif.simulation.vibro_impact`.

Each model comes with its energy and the power balance that the derivation proves symbolically:
``dH/dtau = P`` along solutions.
"""

from __future__ import annotations

import sympy as sp

tau = sp.Symbol("tau", real=True)
X, Xd, w, wd = STATE = sp.symbols("X Xd w wd", real=True)
eps, beta, gamma, sigma, Abar, lam, chi = sp.symbols("eps beta gamma sigma Abar lam chi", real=True)
n, p = sp.symbols("n p", integer=True, nonnegative=True)
PARAMS = (eps, beta, gamma, sigma, Abar, lam, chi, n, p)
REAL_PARAMS = PARAMS[:7]  # the ones a continuation can vary (n and p are integers)
LINEAR_PARAMS = (eps, beta, gamma, sigma)

forcing = eps * Abar * sp.cos(tau)


def smooth_coefficients():
    """The exact coefficients a, b, c, d of (9) (see the module docstring)."""
    detuned = (1 - eps * sigma) / (1 + eps * beta**2)
    return (
        1 - eps * sigma,
        eps * (1 - beta**2) * detuned,
        (1 - beta**2) * detuned,
        (eps + beta**2) * detuned,
    )


def smooth_rhs():
    """Right-hand side of (9) as a column matrix."""
    a, b, c, d = smooth_coefficients()
    damping = eps * gamma * Xd + eps**2 * gamma * wd
    wall = lam * wd * w ** (2 * p) + chi * w ** (2 * n + 1)
    return sp.Matrix([Xd, forcing - a * X - b * w - damping, wd, forcing - c * X - d * w - damping - wall])


def guard_zero_power(expr):
    """Rewrite ``w**(2p)/w`` (what sympy makes of d/dw w**(2p)) as ``w**max(2p-1, 0)``.

    At p = 0 the derivative's coefficient 2p vanishes, but ``0 * w**-1`` is NaN at w = 0; the
    guarded exponent keeps the generated Jacobian finite there and exact for every p >= 0.
    """
    expr = sp.powsimp(expr, force=True)
    return expr.replace(
        lambda e: e.is_Pow and e.base == w and sp.simplify(e.exp - (2 * p - 1)) == 0,
        lambda e: w ** sp.Max(2 * p - 1, 0),
    )


def jacobian(rhs):
    return rhs.jacobian(sp.Matrix(STATE)).applyfunc(guard_zero_power)


def guard_negative_powers(expr):
    """``w**(2p - k)`` as ``w**max(2p - k, 0)`` (k = 1, 2, 3): the second and third derivatives of
    the wall's damping lam w' w^(2p) carry 2p (2p - 1) (2p - 2), which vanishes exactly where the
    power would be negative, so the guarded form is finite at w = 0 and exact for every p >= 0."""
    expr = sp.powsimp(sp.expand(expr), force=True)
    return expr.replace(
        lambda e: e.is_Pow and e.base == w and any(sp.simplify(e.exp - (2 * p - k)) == 0 for k in (1, 2, 3)),
        lambda e: w ** sp.Max(e.exp, 0),
    )


def directional(rhs, *directions):
    """The derivative of ``rhs`` in the state along each of ``directions`` in turn (vectors of
    symbols): f_yy[a, b] for two, f_yyy[a, b, c] for three; the contraction, not the tensor."""
    out = rhs
    for direction in directions:
        out = sum((out.diff(s) * d for s, d in zip(STATE, direction)), sp.zeros(*rhs.shape))
    return out.applyfunc(guard_negative_powers)


def smooth_energy():
    """Energy H of (9): conserved when gamma = lam = Abar = 0 (weights 1 and eps on the two rows)."""
    a, b, c, d = smooth_coefficients()
    kinetic = Xd**2 / 2 + eps * wd**2 / 2
    potential = a * X**2 / 2 + b * X * w + eps * d * w**2 / 2 + eps * chi * w ** (2 * n + 2) / (2 * n + 2)
    return kinetic + potential


def smooth_power():
    """Power balance P = dH/dtau of (9): forcing in, vessel damping and wall dissipation out."""
    momentum = Xd + eps * wd
    return forcing * momentum - eps * gamma * momentum**2 - eps * lam * wd**2 * w ** (2 * p)


def impact_coefficients():
    """Coefficients of (8): those of (9) expanded to O(eps), with the O(eps^2) damping dropped."""
    return tuple(sp.expand(sp.series(k, eps, 0, 2).removeO()) for k in smooth_coefficients())


def impact_rhs():
    """Right-hand side of (8) between impacts (linear in the state)."""
    a, b, c, d = impact_coefficients()
    return sp.Matrix(
        [Xd, forcing - a * X - b * w - eps * gamma * Xd, wd, forcing - c * X - d * w - eps * gamma * Xd]
    )


def flight_rhs():
    """Right-hand side of (9) without the wall (lam = chi = 0): linear in the state, with (9)'s exact
    coefficients and its eps**2 damping. The corrected impact model flies on it between impacts."""
    return smooth_rhs().subs({lam: 0, chi: 0})


def impact_weight():
    """Weight mu = b/c of the w-row in the energy of (8); b/c = eps/(1 - eps(sigma + beta^2))."""
    _, b, c, _ = impact_coefficients()
    return sp.simplify(sp.factor(b) / sp.factor(c))


def impact_energy():
    a, b, c, d = impact_coefficients()
    mu = impact_weight()
    return Xd**2 / 2 + a * X**2 / 2 + b * X * w + mu * (wd**2 / 2 + d * w**2 / 2)


def impact_power():
    mu = impact_weight()
    momentum = Xd + mu * wd
    return forcing * momentum - eps * gamma * Xd * momentum


def time_derivative(H, rhs):
    """dH/dtau along the flow ``y' = rhs``."""
    grad = sp.Matrix([H.diff(s) for s in STATE])
    return sp.diff(H, tau) + (grad.T * rhs)[0]


def check_energy_balances():
    """Prove dH/dtau = P symbolically for both models; raise if either fails."""
    for name, H, P, rhs in [
        ("smooth model (9)", smooth_energy(), smooth_power(), smooth_rhs()),
        ("vibro-impact model (8)", impact_energy(), impact_power(), impact_rhs()),
    ]:
        if sp.simplify(time_derivative(H, rhs) - P) != 0:
            raise AssertionError(f"energy balance of the {name} does not hold symbolically")
