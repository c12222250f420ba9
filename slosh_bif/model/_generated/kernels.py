"""Scalar kernels of the smooth model (9) for the compiled integrator (slosh_bif.simulation.integrator).

GENERATED CODE - DO NOT EDIT.
Written by derivations/generate.py with sympy >=1.14,<1.15 (pinned in pyproject.toml: the printer's
output, including its float spellings such as ``**(-1.0)``, is only reproducible within one series).
Regenerate with `slosh-bif derive` (or `python derivations/generate.py`); `slosh-bif derive --check`
fails when this file is stale. Equations are cited in the hand-written modules that use it.
"""
# fmt: off
# ruff: noqa
import numpy


def smooth_rhs_kernel(tau, y, out, pars):
    """out = f(tau, y) of (9); pars = (eps, beta, gamma, sigma, Abar, lam, chi, n, p)."""
    eps = pars[0]
    beta = pars[1]
    gamma = pars[2]
    sigma = pars[3]
    Abar = pars[4]
    lam = pars[5]
    chi = pars[6]
    n = pars[7]
    p = pars[8]
    X = y[0]
    Xd = y[1]
    w = y[2]
    wd = y[3]
    x0 = eps*sigma - 1
    x1 = beta**2
    x2 = x1 - 1
    x3 = (eps*x1 + 1)**(-1.0)
    x4 = -Abar*eps*numpy.cos(tau) + Xd*eps*gamma + eps**2*gamma*wd
    out[0] = Xd
    out[1] = X*x0 - eps*w*x0*x2*x3 - x4
    out[2] = wd
    out[3] = -X*x0*x2*x3 - chi*w**(2*n + 1) - lam*w**(2*p)*wd + w*x0*x3*(eps + x1) - x4


def smooth_shooting_kernel(tau, z, out, pars):
    """out = d/dtau [y, Phi, dy/dsigma, dy/dAbar, int tr J] for (9), 29 components."""
    eps = pars[0]
    beta = pars[1]
    gamma = pars[2]
    sigma = pars[3]
    Abar = pars[4]
    lam = pars[5]
    chi = pars[6]
    n = pars[7]
    p = pars[8]
    X = z[0]
    Xd = z[1]
    w = z[2]
    wd = z[3]
    phi0 = z[4]
    phi1 = z[5]
    phi2 = z[6]
    phi3 = z[7]
    phi4 = z[8]
    phi5 = z[9]
    phi6 = z[10]
    phi7 = z[11]
    phi8 = z[12]
    phi9 = z[13]
    phi10 = z[14]
    phi11 = z[15]
    phi12 = z[16]
    phi13 = z[17]
    phi14 = z[18]
    phi15 = z[19]
    s0 = z[20]
    s1 = z[21]
    s2 = z[22]
    s3 = z[23]
    q0 = z[24]
    q1 = z[25]
    q2 = z[26]
    q3 = z[27]
    trace = z[28]
    x0 = eps*sigma - 1
    x1 = beta**2
    x2 = (eps*x1 + 1)**(-1.0)
    x3 = x2*(x1 - 1)
    x4 = w*x3
    x5 = eps*x0
    x6 = eps*gamma
    x7 = eps**2
    x8 = gamma*x7
    x9 = numpy.cos(tau)
    x10 = -Abar*eps*x9 + Xd*x6 + wd*x8
    x11 = 2*n
    x12 = x11 + 1
    x13 = 2*p
    x14 = lam*w**x13
    x15 = eps + x1
    x16 = phi4*x6
    x17 = x3*x5
    x18 = phi5*x6
    x19 = phi6*x6
    x20 = phi7*x6
    x21 = x14 + x8
    x22 = chi*w**x11*x12 + lam*w**max(0, x13 - 1)*wd*x13 - x0*x15*x2
    x23 = s1*x6
    x24 = -eps*x9 + q1*x6
    out[0] = Xd
    out[1] = X*x0 - x10 - x4*x5
    out[2] = wd
    out[3] = -X*x0*x3 - chi*w**x12 + w*x0*x15*x2 - wd*x14 - x10
    out[4] = phi4
    out[5] = phi5
    out[6] = phi6
    out[7] = phi7
    out[8] = phi0*x0 - phi12*x8 - phi8*x17 - x16
    out[9] = phi1*x0 - phi13*x8 - phi9*x17 - x18
    out[10] = -phi10*x17 - phi14*x8 + phi2*x0 - x19
    out[11] = -phi11*x17 - phi15*x8 + phi3*x0 - x20
    out[12] = phi12
    out[13] = phi13
    out[14] = phi14
    out[15] = phi15
    out[16] = -phi0*x0*x3 - phi12*x21 - phi8*x22 - x16
    out[17] = -phi1*x0*x3 - phi13*x21 - phi9*x22 - x18
    out[18] = -phi10*x22 - phi14*x21 - phi2*x0*x3 - x19
    out[19] = -phi11*x22 - phi15*x21 - phi3*x0*x3 - x20
    out[20] = s1
    out[21] = X*eps + s0*x0 - s2*x17 - s3*x8 - x23 - x4*x7
    out[22] = s3
    out[23] = -X*eps*x3 + eps*w*x15*x2 - s0*x0*x3 - s2*x22 - s3*x21 - x23
    out[24] = q1
    out[25] = q0*x0 - q2*x17 - q3*x8 - x24
    out[26] = q3
    out[27] = -q0*x0*x3 - q2*x22 - q3*x21 - x24
    out[28] = -x21 - x6
