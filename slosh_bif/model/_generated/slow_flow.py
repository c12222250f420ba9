"""The slow invariant manifold (36), slow flow (45), steady states (46) and kappa on the manifold (39).

GENERATED CODE - DO NOT EDIT.
Written by derivations/generate.py with sympy >=1.14,<1.15 (pinned in pyproject.toml: the printer's
output, including its float spellings such as ``**(-1.0)``, is only reproducible within one series).
Regenerate with `slosh-bif derive` (or `python derivations/generate.py`); `slosh-bif derive --check`
fails when this file is stale. Equations are cited in the hand-written modules that use it.
"""
# fmt: off
# ruff: noqa
import numpy


def sim_alpha(A, rho):
    """alpha on the stable branch S+ of the manifold, eq. (36)."""
    x0 = rho**2
    x1 = x0 + 1
    x2 = x1**(-1.0)
    shape = numpy.broadcast(A, rho).shape
    out = numpy.zeros(shape)
    out[...] = x2*(numpy.sqrt(x1)*numpy.sqrt(A**2 - x0*x2) + 1)
    return out


def sim_alpha_unstable(A, rho):
    """alpha on the unstable branch of the manifold, eq. (36)."""
    x0 = rho**2
    x1 = x0 + 1
    x2 = x1**(-1.0)
    shape = numpy.broadcast(A, rho).shape
    out = numpy.zeros(shape)
    out[...] = -x2*(numpy.sqrt(x1)*numpy.sqrt(A**2 - x0*x2) - 1)
    return out


def sim_a_min(rho):
    """End A_min of the manifold, eq. (36)."""
    shape = numpy.broadcast(rho).shape
    out = numpy.zeros(shape)
    out[...] = rho/numpy.sqrt(rho**2 + 1)
    return out


def sim_alpha_min(rho):
    """alpha at the manifold's end, eq. (36)."""
    shape = numpy.broadcast(rho).shape
    out = numpy.zeros(shape)
    out[...] = (rho**2 + 1)**(-1.0)
    return out


def slow_rhs(A, psi, rho, beta, gamma, sigma, Abar):
    """Forced slow flow (45) on S+: [D1 A, D1 psi]."""
    x0 = numpy.pi**2
    x1 = A*x0
    x2 = rho**2
    x3 = x2 + 1
    x4 = A**2
    x5 = x3**(-1.0)
    x6 = numpy.sqrt(x3)*numpy.sqrt(-x2*x5 + x4) + 1
    x7 = 8*rho*x6**2/x3**2
    x8 = beta**2
    x9 = (1/2)/x0
    x10 = x8 - 1
    x11 = x5*x6
    shape = numpy.broadcast(A, psi).shape
    out = numpy.zeros((2,) + shape)
    out[0] = -x9*(x1*(A*gamma - Abar*numpy.cos(psi)) - x7*x8 + x7)/A
    out[1] = -x9*(Abar*x1*numpy.sin(psi) + x0*x4*(sigma + x10) + 8*x10*x11*(1 - x11))/x4
    return out


def slow_jac(A, psi, rho, drho, beta, gamma, sigma, Abar):
    """Jacobian of (45) in (A, psi); rho = rho(A) with slope drho."""
    x0 = numpy.pi**2
    x1 = x0**(-1.0)
    x2 = A*gamma
    x3 = Abar*numpy.cos(psi)
    x4 = x2 - x3
    x5 = rho**2
    x6 = x5 + 1
    x7 = x6**(-2.0)
    x8 = drho*x7
    x9 = numpy.sqrt(x6)
    x10 = A**2
    x11 = x6**(-1.0)
    x12 = numpy.sqrt(x10 - x11*x5)
    x13 = x12*x9 + 1
    x14 = x13**2
    x15 = 8*x14
    x16 = x15*x8
    x17 = beta**2
    x18 = 32*drho*x14*x5/x6**3
    x19 = A**(-1.0)
    x20 = A*x0
    x21 = rho*x7
    x22 = drho*rho
    x23 = x12*x22/x9 + x9*(A + rho**3*x8 - x11*x22)/x12
    x24 = 16*x13*x21*x23
    x25 = (1/2)*x19
    x26 = Abar*numpy.sin(psi)
    x27 = (1/2)*x26
    x28 = x17 - 1
    x29 = sigma + x28
    x30 = x11*x13
    x31 = 1 - x30
    x32 = x28*x31
    shape = numpy.broadcast(A, psi).shape
    out = numpy.zeros((2, 2) + shape)
    out[0, 0] = -x1*x25*(x0*x2 + x0*x4 - x16*x17 + x16 + x17*x18 - x17*x24 - x18 + x19*(8*rho*x14*x17*x7 - x15*x21 - x20*x4) + x24)
    out[0, 1] = -x27
    out[1, 0] = x1*(8*drho*rho*x13*x28*x31*x7 - x0*x27 - 4*x11*x23*x32 - 4*x13*x28*x7*(2*drho*rho*x11*x13 - x23) + x19*(x0*x10*x29 + x20*x26 + 8*x30*x32) - x20*x29)/x10
    out[1, 1] = -x25*x3
    return out


def slow_dparams(A, psi, rho, beta, gamma, sigma, Abar):
    """Derivatives of (45) in the parameters: columns d/dsigma, d/dAbar."""
    shape = numpy.broadcast(A, psi).shape
    out = numpy.zeros((2, 2) + shape)
    out[0, 1] = (1/2)*numpy.cos(psi)
    out[1, 0] = -1/2
    out[1, 1] = -1/2*numpy.sin(psi)/A
    return out


def steady_residual(A, rho, beta, gamma, sigma, Abar):
    """Steady-state residual (46) on S+ (derived sign)."""
    x0 = A**2
    x1 = numpy.pi**2*x0
    x2 = rho**2
    x3 = x2 + 1
    x4 = x3**(-1.0)
    x5 = numpy.sqrt(x3)*numpy.sqrt(x0 - x2*x4) + 1
    x6 = 8*x5**2/x3**2
    x7 = rho*x6
    x8 = beta**2
    x9 = 8*x4*x5
    shape = numpy.broadcast(A, rho).shape
    out = numpy.zeros(shape)
    out[...] = -numpy.pi**4*Abar**2*x0 + (gamma*x1 - x7*x8 + x7)**2 + (sigma*x1 + x1*x8 - x1 - x6*x8 + x6 + x8*x9 - x9)**2
    return out


def steady_residual_grad(A, rho, drho, beta, gamma, sigma, Abar):
    """[dR/dA, dR/dsigma, dR/dAbar] of (46); rho = rho(A) with slope drho."""
    x0 = numpy.pi**4
    x1 = numpy.pi**2
    x2 = A**2
    x3 = x1*x2
    x4 = rho**2
    x5 = x4 + 1
    x6 = x5**(-2.0)
    x7 = numpy.sqrt(x5)
    x8 = x5**(-1.0)
    x9 = numpy.sqrt(x2 - x4*x8)
    x10 = x7*x9 + 1
    x11 = x10**2
    x12 = 8*x11*x6
    x13 = rho*x12
    x14 = beta**2
    x15 = A*x1
    x16 = drho*x6
    x17 = 4*x11*x16
    x18 = 16*x11/x5**3
    x19 = drho*x18*x4
    x20 = drho*rho
    x21 = x20*x9/x7 + x7*(A + rho**3*x16 - x20*x8)/x9
    x22 = 8*x10
    x23 = x21*x22*x6
    x24 = rho*x23
    x25 = rho*x16*x22
    x26 = x18*x20
    x27 = 4*x21*x8
    x28 = x22*x8
    x29 = 2*sigma*x3 - 2*x12*x14 + 2*x12 + 2*x14*x28 + 2*x14*x3 - 2*x28 - 2*x3
    shape = numpy.broadcast(A, rho).shape
    out = numpy.zeros((3,) + shape)
    out[0] = -2*A*Abar**2*x0 + 2*x29*(sigma*x15 + x14*x15 - x14*x23 - x14*x25 + x14*x26 + x14*x27 - x15 + x23 + x25 - x26 - x27) + 4*(gamma*x3 - x13*x14 + x13)*(gamma*x15 - x14*x17 + x14*x19 - x14*x24 + x17 - x19 + x24)
    out[1] = x29*x3
    out[2] = -2*Abar*x0*x2
    return out


def steady_balances(A, rho, beta, gamma, sigma, Abar):
    """[pi^2 A Abar cos psi, pi^2 A Abar sin psi] at a steady state of (45)."""
    x0 = numpy.pi**2
    x1 = A**2
    x2 = x0*x1
    x3 = rho**2
    x4 = x3 + 1
    x5 = x4**(-2.0)
    x6 = x4**(-1.0)
    x7 = numpy.sqrt(x4)*numpy.sqrt(x1 - x3*x6) + 1
    x8 = x7**2
    x9 = 8*x5*x8
    x10 = rho*x9
    x11 = beta**2
    shape = numpy.broadcast(A, rho).shape
    out = numpy.zeros((2,) + shape)
    out[0] = gamma*x2 - x10*x11 + x10
    out[1] = -sigma*x2 + x0*x1 - x11*x2 + 8*x11*x5*x8 - 8*x11*x6*x7 + 8*x6*x7 - x9
    return out


def slow_rhs_end(psi, rho, beta, gamma, sigma, Abar):
    """Forced slow flow (45) at the manifold's end (36), A = A_min, alpha = alpha_min: [D1 A, D1 psi]."""
    x0 = numpy.pi**2
    x1 = x0**(-1.0)
    x2 = rho**2 + 1
    x3 = beta**2
    x4 = Abar*numpy.sqrt(x2)
    x5 = x2**(-1.0)
    shape = numpy.broadcast(psi).shape
    out = numpy.zeros((2,) + shape)
    out[0] = (1/2)*x1*(x0*x2*(-gamma*rho + x4*numpy.cos(psi)) + 8*x3 - 8)/x2**(3/2)
    out[1] = -1/2*sigma - 4*x1*x3*x5 + 4*x1*x5 - 1/2*x3 + 1/2 - 1/2*x4*numpy.sin(psi)/rho
    return out


def slow_end_jac(psi, rho, beta, gamma, sigma, Abar):
    """Derivatives of (45) at the manifold's end in psi, sigma and Abar (rows D1 A, D1 psi)."""
    x0 = (1/2)*numpy.sin(psi)
    x1 = (1/2)*numpy.cos(psi)
    x2 = numpy.sqrt(rho**2 + 1)/rho
    shape = numpy.broadcast(psi).shape
    out = numpy.zeros((2, 3) + shape)
    out[0, 0] = -Abar*x0
    out[0, 2] = x1
    out[1, 0] = -Abar*x1*x2
    out[1, 1] = -1/2
    out[1, 2] = -x0*x2
    return out


def steady_residual_end(rho, beta, gamma, sigma, Abar):
    """[R, dR/dsigma, dR/dAbar] of (46) at the manifold's end (36), A = A_min, alpha = alpha_min."""
    x0 = rho**2
    x1 = x0 + 1
    x2 = x1**3
    x3 = numpy.pi**4*x0
    x4 = numpy.pi**2
    x5 = beta**2
    x6 = 8*x5
    x7 = 8 - x6
    x8 = x0*x4
    x9 = x1*(sigma*x8 + x5*x8 + x6 - x8 - 8) + x7
    shape = numpy.broadcast(rho).shape
    out = numpy.zeros((3,) + shape)
    out[0] = (-Abar**2*x2*x3 + x0*(gamma*rho*x1*x4 + x7)**2 + x9**2)/x1**4
    out[1] = 2*x8*x9/x2
    out[2] = -2*Abar*x3/x1
    return out


def manifold_kappa_residual(kappa, A, delta1, expo):
    """kappa^2 - 1 + delta1 v^expo with v the impact speed (38), eq. (39)."""
    x0 = kappa + 1
    x1 = 4*(kappa - 1)**2/(numpy.pi**2*x0**2)
    x2 = x1 + 1
    x3 = x2**(-1.0)
    shape = numpy.broadcast(kappa, A).shape
    out = numpy.zeros(shape)
    out[...] = delta1*(4*x3*(numpy.sqrt(x2)*numpy.sqrt(A**2 - x1*x3) + 1)/(numpy.pi*x0))**expo + kappa**2 - 1
    return out


def manifold_kappa_residual_grad(kappa, A, delta1, expo):
    """[d/dkappa, d/dA] of the residual of eq. (39)."""
    x0 = kappa + 1
    x1 = x0**(-1.0)
    x2 = kappa - 1
    x3 = x2**2
    x4 = x1*x3
    x5 = -kappa + x4 + 1
    x6 = numpy.pi**(-2.0)
    x7 = 4*x6
    x8 = x7/x0**2
    x9 = x2**2*x8
    x10 = x9 + 1
    x11 = numpy.sqrt(x10)
    x12 = x10**(-1.0)
    x13 = numpy.sqrt(A**2 - x12*x9)
    x14 = x3*x8
    x15 = (x14 + 1)**(-1.0)
    x16 = x11/x13
    x17 = x11*x13 + 1
    x18 = delta1*expo*(4*x1*x12*x17/numpy.pi)**expo/x17
    shape = numpy.broadcast(kappa, A).shape
    out = numpy.zeros((2,) + shape)
    out[0] = 2*kappa + x1*x18*(8*x1*x12*x17*x2*x6*(x1*x2 - 1) - x1*x7*(x15*x16*(x14*x15*x5 + x2 - x4) + x13*x5/x11) - x17)
    out[1] = A*x16*x18
    return out
