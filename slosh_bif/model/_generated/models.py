"""Right-hand sides, Jacobians and energies of models (8) and (9).

GENERATED CODE - DO NOT EDIT.
Written by derivations/generate.py with sympy >=1.14,<1.15 (pinned in pyproject.toml: the printer's
output, including its float spellings such as ``**(-1.0)``, is only reproducible within one series).
Regenerate with `slosh-bif derive` (or `python derivations/generate.py`); `slosh-bif derive --check`
fails when this file is stale. Equations are cited in the hand-written modules that use it.
"""
# fmt: off
# ruff: noqa
import numpy


def smooth_rhs(tau, y, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """Right-hand side of the smooth model (9); y = [X, X', w, w']."""
    X, Xd, w, wd = y
    x0 = eps*sigma - 1
    x1 = beta**2
    x2 = x1 - 1
    x3 = (eps*x1 + 1)**(-1.0)
    x4 = -Abar*eps*numpy.cos(tau) + Xd*eps*gamma + eps**2*gamma*wd
    shape = numpy.broadcast(X, Xd, w, wd, tau).shape
    out = numpy.zeros((4,) + shape)
    out[0] = Xd
    out[1] = X*x0 - eps*w*x0*x2*x3 - x4
    out[2] = wd
    out[3] = -X*x0*x2*x3 - chi*w**(2*n + 1) - lam*w**(2*p)*wd + w*x0*x3*(eps + x1) - x4
    return out


def smooth_second(tau, y, a, b, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """Second derivative of (9)'s right-hand side along a and b, f_yy[a, b] (the wall's terms)."""
    X, Xd, w, wd = y
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    x0 = a2*b2
    x1 = chi*w**(2*n - 1)*x0
    x2 = lam*p*w**max(0, 2*p - 1)
    x3 = w**max(0, 2*(p - 1))
    shape = numpy.broadcast(X, Xd, w, wd, a0, a1, a2, a3, b0, b1, b2, b3, tau).shape
    out = numpy.zeros((4,) + shape)
    out[3] = 2*a2*b2*lam*p*wd*x3 - 2*a2*b3*x2 - 2*a3*b2*x2 - 4*lam*p**2*wd*x0*x3 - 4*n**2*x1 - 2*n*x1
    return out


def smooth_third(tau, y, a, b, c, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """Third derivative of (9)'s right-hand side along a, b and c, f_yyy[a, b, c]."""
    X, Xd, w, wd = y
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    c0, c1, c2, c3 = c
    x0 = w**(2*n - 2)
    x1 = a2*b2
    x2 = c2*x1
    x3 = w**max(0, 2*(p - 1))
    x4 = 2*p
    x5 = w**max(0, x4 - 3)
    x6 = lam*wd*x2*x5
    x7 = p**2
    x8 = 2*lam*x3*x7
    x9 = c2*x8
    shape = numpy.broadcast(X, Xd, w, wd, a0, a1, a2, a3, b0, b1, b2, b3, c0, c1, c2, c3, tau).shape
    out = numpy.zeros((4,) + shape)
    out[3] = 2*a2*b2*c2*chi*n*x0 + 12*a2*b2*c2*lam*wd*x5*x7 + 2*a2*b2*c3*lam*p*x3 + 2*a2*b3*c2*lam*p*x3 - 2*a2*b3*x9 + 2*a3*b2*c2*lam*p*x3 - 2*a3*b2*x9 - 2*c3*x1*x8 - 8*chi*n**3*x0*x2 - 8*p**3*x6 - 2*x4*x6
    return out


def smooth_jac(tau, y, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """Jacobian d(rhs)/dy of the smooth model (9), shape (4, 4, ...)."""
    X, Xd, w, wd = y
    x0 = eps*sigma - 1
    x1 = -eps*gamma
    x2 = beta**2
    x3 = (eps*x2 + 1)**(-1.0)
    x4 = x0*x3*(x2 - 1)
    x5 = eps**2*gamma
    x6 = 2*n
    x7 = 2*p
    shape = numpy.broadcast(X, Xd, w, wd, tau).shape
    out = numpy.zeros((4, 4) + shape)
    out[0, 1] = 1
    out[1, 0] = x0
    out[1, 1] = x1
    out[1, 2] = -eps*x4
    out[1, 3] = -x5
    out[2, 3] = 1
    out[3, 0] = -x4
    out[3, 1] = x1
    out[3, 2] = -chi*w**x6*(x6 + 1) - lam*w**max(0, x7 - 1)*wd*x7 + x0*x3*(eps + x2)
    out[3, 3] = -lam*w**x7 - x5
    return out


def smooth_variational(tau, y, Phi, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """Variational equations of (9): d/dtau [y, Phi] = [f(y), J(y) Phi], Phi row-major (16,)."""
    X, Xd, w, wd = y
    phi0, phi1, phi2, phi3, phi4, phi5, phi6, phi7, phi8, phi9, phi10, phi11, phi12, phi13, phi14, phi15 = Phi
    x0 = eps*sigma - 1
    x1 = beta**2
    x2 = (eps*x1 + 1)**(-1.0)
    x3 = x2*(x1 - 1)
    x4 = eps*x3
    x5 = eps*gamma
    x6 = eps**2*gamma
    x7 = -Abar*eps*numpy.cos(tau) + Xd*x5 + wd*x6
    x8 = 2*n
    x9 = x8 + 1
    x10 = 2*p
    x11 = lam*w**x10
    x12 = eps + x1
    x13 = phi4*x5
    x14 = x0*x4
    x15 = phi5*x5
    x16 = phi6*x5
    x17 = phi7*x5
    x18 = x11 + x6
    x19 = chi*w**x8*x9 + lam*w**max(0, x10 - 1)*wd*x10 - x0*x12*x2
    shape = numpy.broadcast(X, Xd, w, wd, phi0, phi1, phi2, phi3, phi4, phi5, phi6, phi7, phi8, phi9, phi10, phi11, phi12, phi13, phi14, phi15, tau).shape
    out = numpy.zeros((20,) + shape)
    out[0] = Xd
    out[1] = X*x0 - w*x0*x4 - x7
    out[2] = wd
    out[3] = -X*x0*x3 - chi*w**x9 + w*x0*x12*x2 - wd*x11 - x7
    out[4] = phi4
    out[5] = phi5
    out[6] = phi6
    out[7] = phi7
    out[8] = phi0*x0 - phi12*x6 - phi8*x14 - x13
    out[9] = phi1*x0 - phi13*x6 - phi9*x14 - x15
    out[10] = -phi10*x14 - phi14*x6 + phi2*x0 - x16
    out[11] = -phi11*x14 - phi15*x6 + phi3*x0 - x17
    out[12] = phi12
    out[13] = phi13
    out[14] = phi14
    out[15] = phi15
    out[16] = -phi0*x0*x3 - phi12*x18 - phi8*x19 - x13
    out[17] = -phi1*x0*x3 - phi13*x18 - phi9*x19 - x15
    out[18] = -phi10*x19 - phi14*x18 - phi2*x0*x3 - x16
    out[19] = -phi11*x19 - phi15*x18 - phi3*x0*x3 - x17
    return out


def smooth_energy(y, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """Energy H of the smooth model (9)."""
    X, Xd, w, wd = y
    x0 = (1/2)*eps
    x1 = eps*sigma - 1
    x2 = beta**2
    x3 = x1/(eps*x2 + 1)
    shape = numpy.broadcast(X, Xd, w, wd).shape
    out = numpy.zeros(shape)
    out[...] = -1/2*X**2*x1 + X*eps*w*x3*(x2 - 1) + (1/2)*Xd**2 + chi*w**(2*n + 2)*x0/(n + 1) - w**2*x0*x3*(eps + x2) + wd**2*x0
    return out


def smooth_power(tau, y, eps, beta, gamma, sigma, Abar, lam, chi, n, p):
    """dH/dtau of the smooth model (9) along solutions."""
    X, Xd, w, wd = y
    x0 = Xd + eps*wd
    shape = numpy.broadcast(X, Xd, w, wd, tau).shape
    out = numpy.zeros(shape)
    out[...] = eps*(Abar*x0*numpy.cos(tau) - gamma*x0**2 - lam*w**(2*p)*wd**2)
    return out


def impact_matrix(eps, beta, gamma, sigma):
    """Matrix M of the linear flow y' = M y + F cos(tau) of model (8)."""
    x0 = eps*sigma
    x1 = -eps*gamma
    x2 = beta**2
    x3 = beta**4*eps + x0*x2 - x2
    shape = ()
    out = numpy.zeros((4, 4) + shape)
    out[0, 1] = 1
    out[1, 0] = x0 - 1
    out[1, 1] = x1
    out[1, 2] = eps*(x2 - 1)
    out[2, 3] = 1
    out[3, 0] = eps*sigma + eps*x2 - x3 - 1
    out[3, 1] = x1
    out[3, 2] = -eps + x3
    return out


def flight_matrix(eps, beta, gamma, sigma):
    """Matrix M of (9) without the wall (lam = chi = 0): the flights of the corrected impact model."""
    x0 = eps*sigma - 1
    x1 = -eps*gamma
    x2 = beta**2
    x3 = x0/(eps*x2 + 1)
    x4 = x3*(x2 - 1)
    x5 = -eps**2*gamma
    shape = ()
    out = numpy.zeros((4, 4) + shape)
    out[0, 1] = 1
    out[1, 0] = x0
    out[1, 1] = x1
    out[1, 2] = -eps*x4
    out[1, 3] = x5
    out[2, 3] = 1
    out[3, 0] = -x4
    out[3, 1] = x1
    out[3, 2] = x3*(eps + x2)
    out[3, 3] = x5
    return out


def impact_linear_derivatives(eps, beta, gamma, sigma, Abar):
    """[dM/dq | dF/dq] of model (8) for q = eps, beta, gamma, sigma, Abar, stacked (20 x 5)."""
    x0 = -gamma
    x1 = beta**2
    x2 = x1 - 1
    x3 = beta**4 + sigma*x1
    x4 = 2*beta
    x5 = -eps
    x6 = eps*x1
    x7 = eps*sigma + 2*x6 - 1
    shape = ()
    out = numpy.zeros((20, 5) + shape)
    out[1, 0] = sigma
    out[1, 1] = x0
    out[1, 2] = x2
    out[1, 4] = Abar
    out[3, 0] = sigma + x1 - x3
    out[3, 1] = x0
    out[3, 2] = x3 - 1
    out[3, 4] = Abar
    out[5, 2] = eps*x4
    out[7, 0] = x4*(-x5 - x7)
    out[7, 2] = x4*x7
    out[9, 1] = x5
    out[11, 1] = x5
    out[13, 0] = eps
    out[15, 0] = -eps*x2
    out[15, 2] = x6
    out[17, 4] = eps
    out[19, 4] = eps
    return out


def flight_linear_derivatives(eps, beta, gamma, sigma, Abar):
    """[dM/dq | dF/dq] of (9)'s flights for q = eps, beta, gamma, sigma, Abar, stacked (20 x 5)."""
    x0 = -gamma
    x1 = eps*sigma
    x2 = beta**2
    x3 = eps*x2
    x4 = (x3 + 1)**(-1.0)
    x5 = x4*(x1 - 1)
    x6 = x4*(x2 - 1)
    x7 = 2*eps
    x8 = -gamma*x7
    x9 = x2*x5
    x10 = eps + x2
    x11 = eps*x6
    x12 = x11 - 1
    x13 = 2*beta*x5
    x14 = eps*x10*x4
    x15 = -eps
    x16 = eps**2
    x17 = -x16
    shape = ()
    out = numpy.zeros((20, 5) + shape)
    out[1, 0] = sigma
    out[1, 1] = x0
    out[1, 2] = x6*(-2*x1 + x3*x5 + 1)
    out[1, 3] = x8
    out[1, 4] = Abar
    out[3, 0] = x6*(-sigma + x9)
    out[3, 1] = x0
    out[3, 2] = x4*(eps*sigma + sigma*x10 - x10*x9 - 1)
    out[3, 3] = x8
    out[3, 4] = Abar
    out[5, 2] = beta*x12*x5*x7
    out[7, 0] = x12*x13
    out[7, 2] = x13*(1 - x14)
    out[9, 1] = x15
    out[9, 3] = x17
    out[11, 1] = x15
    out[11, 3] = x17
    out[13, 0] = eps
    out[13, 2] = -x16*x6
    out[15, 0] = -x11
    out[15, 2] = x14
    out[17, 4] = eps
    out[19, 4] = eps
    return out


def impact_forcing(eps, Abar):
    """Forcing vector F of the linear flow of model (8)."""
    x0 = Abar*eps
    shape = ()
    out = numpy.zeros((4,) + shape)
    out[1] = x0
    out[3] = x0
    return out


def impact_weight(eps, beta, sigma):
    """Weight mu of the w-row in the energy of model (8)."""
    shape = ()
    out = numpy.zeros(shape)
    out[...] = -eps/(beta**2*eps + eps*sigma - 1)
    return out


def impact_energy(y, eps, beta, gamma, sigma):
    """Energy H of model (8) between impacts."""
    X, Xd, w, wd = y
    x0 = beta**2
    x1 = eps*sigma
    x2 = x1 - 1
    shape = numpy.broadcast(X, Xd, w, wd).shape
    out = numpy.zeros(shape)
    out[...] = -1/2*X**2*x2 - X*eps*w*(x0 - 1) + (1/2)*Xd**2 - 1/2*eps*(-w**2*(beta**4*eps - eps + x0*x1 - x0) + wd**2)/(eps*x0 + x2)
    return out


def impact_power(tau, y, eps, beta, gamma, sigma, Abar):
    """dH/dtau of model (8) between impacts."""
    X, Xd, w, wd = y
    shape = numpy.broadcast(X, Xd, w, wd, tau).shape
    out = numpy.zeros(shape)
    out[...] = eps*(Xd - eps*wd/(beta**2*eps + eps*sigma - 1))*(Abar*numpy.cos(tau) - Xd*gamma)
    return out
