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


def corrected_alpha(A, rho, D):
    """alpha on S+ with the wall at |w| = D, eq. (36) with clearance D."""
    x0 = rho**2
    x1 = x0 + 1
    x2 = x1**(-1.0)
    shape = numpy.broadcast(A, rho, D).shape
    out = numpy.zeros(shape)
    out[...] = x2*(D + numpy.sqrt(x1)*numpy.sqrt(A**2 - D**2*x0*x2))
    return out


def corrected_alpha_unstable(A, rho, D):
    """alpha on the unstable branch with the wall at |w| = D."""
    x0 = rho**2
    x1 = x0 + 1
    x2 = x1**(-1.0)
    shape = numpy.broadcast(A, rho, D).shape
    out = numpy.zeros(shape)
    out[...] = x2*(D - numpy.sqrt(x1)*numpy.sqrt(A**2 - D**2*x0*x2))
    return out


def corrected_a_min(rho, D):
    """End A_min = D rho / sqrt(1 + rho^2) of the manifold with clearance D."""
    shape = numpy.broadcast(rho, D).shape
    out = numpy.zeros(shape)
    out[...] = D*rho/numpy.sqrt(rho**2 + 1)
    return out


def corrected_slow_rhs(A, psi, rho, D, beta, gamma, sigma, Abar):
    """Slow flow (45) on S+ with clearance D: [D1 A, D1 psi]."""
    x0 = numpy.pi**2
    x1 = A*x0
    x2 = rho**2
    x3 = x2 + 1
    x4 = A**2
    x5 = x3**(-1.0)
    x6 = D + numpy.sqrt(x3)*numpy.sqrt(-D**2*x2*x5 + x4)
    x7 = 8*rho*x6**2/x3**2
    x8 = beta**2
    x9 = (1/2)/x0
    x10 = x8 - 1
    x11 = x5*x6
    shape = numpy.broadcast(A, psi).shape
    out = numpy.zeros((2,) + shape)
    out[0] = -x9*(x1*(A*gamma - Abar*numpy.cos(psi)) - x7*x8 + x7)/A
    out[1] = -x9*(Abar*x1*numpy.sin(psi) + x0*x4*(sigma + x10) + 8*x10*x11*(D - x11))/x4
    return out


def corrected_slow_jac(A, psi, rho, drho, D, dD, beta, gamma, sigma, Abar):
    """Jacobian of the corrected (45) in (A, psi); rho(A), D(A) with slopes drho, dD."""
    x0 = numpy.pi**2
    x1 = x0**(-1.0)
    x2 = A*gamma
    x3 = Abar*numpy.cos(psi)
    x4 = x2 - x3
    x5 = rho**2
    x6 = x5 + 1
    x7 = numpy.sqrt(x6)
    x8 = A**2
    x9 = D**2
    x10 = x6**(-1.0)
    x11 = x10*x5
    x12 = numpy.sqrt(-x11*x9 + x8)
    x13 = D + x12*x7
    x14 = x13**2
    x15 = 8*x14
    x16 = x6**(-2.0)
    x17 = drho*x16
    x18 = x15*x17
    x19 = beta**2
    x20 = 32*drho*x14*x5/x6**3
    x21 = A**(-1.0)
    x22 = A*x0
    x23 = rho*x16
    x24 = drho*rho
    x25 = dD + x12*x24/x7 + x7*(A - D*dD*x11 + rho**3*x17*x9 - x10*x24*x9)/x12
    x26 = x13*x23
    x27 = 16*x25*x26
    x28 = (1/2)*x21
    x29 = Abar*numpy.sin(psi)
    x30 = (1/2)*x29
    x31 = x19 - 1
    x32 = sigma + x31
    x33 = x10*x13
    x34 = D - x33
    x35 = x31*x33
    x36 = x10*x25
    shape = numpy.broadcast(A, psi).shape
    out = numpy.zeros((2, 2) + shape)
    out[0, 0] = -x1*x28*(x0*x2 + x0*x4 - x18*x19 + x18 + x19*x20 - x19*x27 - x20 + x21*(8*rho*x14*x16*x19 - x15*x23 - x22*x4) + x27)
    out[0, 1] = -x30
    out[1, 0] = x1*(8*drho*rho*x13*x16*x31*x34 - x0*x30 + x21*(x0*x32*x8 + x22*x29 + 8*x34*x35) - x22*x32 - 4*x31*x34*x36 - 4*x35*(dD + 2*drho*x26 - x36))/x8
    out[1, 1] = -x28*x3
    return out


def corrected_slow_dparams(A, psi, rho, D, beta, gamma, sigma, Abar):
    """Derivatives of the corrected (45) in sigma and Abar (columns)."""
    shape = numpy.broadcast(A, psi).shape
    out = numpy.zeros((2, 2) + shape)
    out[0, 1] = (1/2)*numpy.cos(psi)
    out[1, 0] = -1/2
    out[1, 1] = -1/2*numpy.sin(psi)/A
    return out


def corrected_steady_residual(A, rho, D, beta, gamma, sigma, Abar):
    """Steady-state residual (46) with clearance D."""
    x0 = A**2
    x1 = numpy.pi**2*x0
    x2 = rho**2
    x3 = x2 + 1
    x4 = x3**(-1.0)
    x5 = D + numpy.sqrt(x3)*numpy.sqrt(-D**2*x2*x4 + x0)
    x6 = 8*x5**2/x3**2
    x7 = rho*x6
    x8 = beta**2
    x9 = 8*D*x4*x5
    shape = numpy.broadcast(A, rho, D).shape
    out = numpy.zeros(shape)
    out[...] = -numpy.pi**4*Abar**2*x0 + (gamma*x1 - x7*x8 + x7)**2 + (sigma*x1 + x1*x8 - x1 - x6*x8 + x6 + x8*x9 - x9)**2
    return out


def corrected_steady_residual_grad(A, rho, drho, D, dD, beta, gamma, sigma, Abar):
    """[dR/dA, dR/dsigma, dR/dAbar] of the corrected (46); slopes drho, dD."""
    x0 = numpy.pi**4
    x1 = numpy.pi**2
    x2 = A**2
    x3 = x1*x2
    x4 = rho**2
    x5 = x4 + 1
    x6 = x5**(-2.0)
    x7 = numpy.sqrt(x5)
    x8 = D**2
    x9 = x5**(-1.0)
    x10 = x4*x9
    x11 = numpy.sqrt(-x10*x8 + x2)
    x12 = D + x11*x7
    x13 = x12**2
    x14 = x13*x6
    x15 = 8*x14
    x16 = rho*x15
    x17 = beta**2
    x18 = A*x1
    x19 = 4*drho*x14
    x20 = 16*x13/x5**3
    x21 = drho*x20*x4
    x22 = drho*rho
    x23 = drho*x8
    x24 = dD + x11*x22/x7 + x7*(A - D*dD*x10 + rho**3*x23*x6 - rho*x23*x9)/x11
    x25 = x12*x6
    x26 = 8*x24*x25
    x27 = rho*x26
    x28 = x12*x9
    x29 = 4*dD*x28
    x30 = 8*D
    x31 = x22*x25*x30
    x32 = x20*x22
    x33 = 4*D*x24*x9
    x34 = x28*x30
    x35 = 2*sigma*x3 - 2*x15*x17 + 2*x15 + 2*x17*x3 + 2*x17*x34 - 2*x3 - 2*x34
    shape = numpy.broadcast(A, rho, D).shape
    out = numpy.zeros((3,) + shape)
    out[0] = -2*A*Abar**2*x0 + 2*x35*(sigma*x18 + x17*x18 - x17*x26 + x17*x29 - x17*x31 + x17*x32 + x17*x33 - x18 + x26 - x29 + x31 - x32 - x33) + 4*(gamma*x3 - x16*x17 + x16)*(gamma*x18 - x17*x19 + x17*x21 - x17*x27 + x19 - x21 + x27)
    out[1] = x3*x35
    out[2] = -2*Abar*x0*x2
    return out


def corrected_steady_balances(A, rho, D, beta, gamma, sigma, Abar):
    """[pi^2 A Abar cos psi, pi^2 A Abar sin psi] at a steady state of the corrected (45)."""
    x0 = numpy.pi**2
    x1 = A**2
    x2 = x0*x1
    x3 = rho**2
    x4 = x3 + 1
    x5 = x4**(-2.0)
    x6 = x4**(-1.0)
    x7 = D + numpy.sqrt(x4)*numpy.sqrt(-D**2*x3*x6 + x1)
    x8 = x7**2
    x9 = 8*x5*x8
    x10 = rho*x9
    x11 = beta**2
    shape = numpy.broadcast(A, rho, D).shape
    out = numpy.zeros((2,) + shape)
    out[0] = gamma*x2 - x10*x11 + x10
    out[1] = -8*D*x11*x6*x7 + 8*D*x6*x7 - sigma*x2 + x0*x1 - x11*x2 + 8*x11*x5*x8 - x9
    return out


def corrected_slow_rhs_end(psi, rho, D, beta, gamma, sigma, Abar):
    """The corrected (45) at the manifold's end, A = A_min(rho, D): [D1 A, D1 psi]."""
    x0 = numpy.pi**2
    x1 = x0**(-1.0)
    x2 = rho**2 + 1
    x3 = beta**2
    x4 = Abar*numpy.sqrt(x2)
    x5 = x2**(-1.0)
    shape = numpy.broadcast(psi).shape
    out = numpy.zeros((2,) + shape)
    out[0] = (1/2)*x1*(8*D*(x3 - 1) + x0*x2*(-D*gamma*rho + x4*numpy.cos(psi)))/x2**(3/2)
    out[1] = -1/2*sigma - 4*x1*x3*x5 + 4*x1*x5 - 1/2*x3 + 1/2 - 1/2*x4*numpy.sin(psi)/(D*rho)
    return out


def corrected_slow_end_jac(psi, rho, D, beta, gamma, sigma, Abar):
    """Derivatives of the corrected (45) at the manifold's end in psi, sigma, Abar."""
    x0 = (1/2)*numpy.sin(psi)
    x1 = (1/2)*numpy.cos(psi)
    x2 = numpy.sqrt(rho**2 + 1)/(D*rho)
    shape = numpy.broadcast(psi).shape
    out = numpy.zeros((2, 3) + shape)
    out[0, 0] = -Abar*x0
    out[0, 2] = x1
    out[1, 0] = -Abar*x1*x2
    out[1, 1] = -1/2
    out[1, 2] = -x0*x2
    return out


def corrected_steady_residual_end(rho, D, beta, gamma, sigma, Abar):
    """[R, dR/dsigma, dR/dAbar] of the corrected (46) at the manifold's end."""
    x0 = D**2
    x1 = rho**2
    x2 = x1 + 1
    x3 = x2**3
    x4 = numpy.pi**4*x1
    x5 = numpy.pi**2
    x6 = beta**2
    x7 = 8*x6
    x8 = 8 - x7
    x9 = x1*x5
    x10 = x2*(sigma*x9 + x6*x9 + x7 - x9 - 8) + x8
    shape = numpy.broadcast(rho).shape
    out = numpy.zeros((3,) + shape)
    out[0] = -x0*(Abar**2*x3*x4 - x0*(x1*(gamma*rho*x2*x5 + x8)**2 + x10**2))/x2**4
    out[1] = 2*D**4*x10*x9/x3
    out[2] = -2*Abar*x0*x4/x2
    return out


def corrected_impact_speed(A, kappa, D):
    """[v, dv/dA, dv/dkappa, dv/dD]: the impact speed (38) on S+ with clearance D."""
    x0 = kappa - 1
    x1 = kappa + 1
    x2 = x1**(-2.0)
    x3 = numpy.pi**(-2.0)
    x4 = 4*x3
    x5 = x2*x4
    x6 = x0**2*x5
    x7 = x6 + 1
    x8 = x7**(-1.0)
    x9 = numpy.sqrt(x7)
    x10 = D**2
    x11 = numpy.sqrt(A**2 - x10*x6*x8)
    x12 = D + x11*x9
    x13 = x1**(-1.0)
    x14 = 4/numpy.pi
    x15 = x13*x14
    x16 = x9**(-1.0)
    x17 = x11**(-1.0)
    x18 = x16*x17
    x19 = x0**2
    x20 = x13*x19
    x21 = -kappa + x20 + 1
    x22 = x19*x5
    x23 = (x22 + 1)**(-1.0)
    shape = numpy.broadcast(A, kappa, D).shape
    out = numpy.zeros((4,) + shape)
    out[0] = x12*x15*x8
    out[1] = A*x15*x18
    out[2] = x14*x2*x8*(8*x0*x12*x13*x3*x8*(x0*x13 - 1) - x12 - x13*x4*(x10*x17*x23*x9*(x0 - x20 + x21*x22*x23) + x11*x16*x21))
    out[3] = -x15*x8*(D*x18*x6 - 1)
    return out


def corrected_end_speed(kappa, D):
    """[v, dv/dkappa, dv/dD]: the impact speed at the manifold's end (alpha = alpha_min)."""
    x0 = kappa + 1
    x1 = numpy.pi**2
    x2 = (x0**2*x1 + 4*(kappa - 1)**2)**(-1.0)
    x3 = x0*x2
    x4 = 4*numpy.pi
    x5 = x3*x4
    shape = numpy.broadcast(kappa).shape
    out = numpy.zeros((3,) + shape)
    out[0] = D*x5
    out[1] = D*x2*x4*(-2*x3*(4*kappa + x0*x1 - 4) + 1)
    out[2] = x5
    return out
