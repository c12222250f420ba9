"""The impact of the vibro-impact model (8): its reset and saltation matrix, for the compiled flow (slosh_bif.flows.impact_flow).

GENERATED CODE - DO NOT EDIT.
Written by derivations/generate.py with sympy >=1.14,<1.15 (pinned in pyproject.toml: the printer's
output, including its float spellings such as ``**(-1.0)``, is only reproducible within one series).
Regenerate with `slosh-bif derive` (or `python derivations/generate.py`); `slosh-bif derive --check`
fails when this file is stale. Equations are cited in the hand-written modules that use it.
"""
# fmt: off
# ruff: noqa
import numpy

from slosh_bif.model.powers import int_power


def impact_saltation_kernel(tau, y, out, pars):
    """out = [S (16, row-major), w'+, dw'+/dloss] of an impact of (8) on either wall (eqs. 2, 8, 21); y is the state before it, pars = (eps, beta, gamma, sigma, Abar, loss, q)."""
    eps = pars[0]
    beta = pars[1]
    gamma = pars[2]
    sigma = pars[3]
    Abar = pars[4]
    loss = pars[5]
    q = pars[6]
    X = y[0]
    Xd = y[1]
    w = y[2]
    wd = y[3]
    x0 = loss - 1
    x1 = numpy.sqrt(-x0)
    x2 = loss*q
    x3 = beta**2
    x4 = eps*sigma
    x5 = beta**4*eps + x3*x4 - x3
    x6 = x1**(-1.0)
    x7 = (1/2)*x6
    out[0] = 1
    out[1] = 0
    out[2] = 0
    out[3] = 0
    out[4] = 0
    out[5] = 1
    out[6] = 0
    out[7] = 0
    out[8] = 0
    out[9] = 0
    out[10] = -x1
    out[11] = 0
    out[12] = 0
    out[13] = 0
    out[14] = x7*(-2*loss + 2*x1 - x2 + 2)*(Abar*eps*numpy.cos(tau) - X*(-eps*x3 - x4 + x5 + 1) - Xd*eps*gamma + w*(-eps + x5))/wd
    out[15] = x6*(x0 + (1/2)*x2)
    out[16] = -wd*x1
    out[17] = wd*x7


def impact_measured_kernel(tau, y, out, pars):
    """out = [S (16, row-major), w'+] of an impact of the corrected impact model on the wall side (eqs. 2, 8; the wall at |w| = D(v) with restitution kappa(v) of the measured wall); y is the state before it, pars = (eps, beta, gamma, sigma, Abar, side, kappa, kappa'(v), D'(v))."""
    eps = pars[0]
    beta = pars[1]
    gamma = pars[2]
    sigma = pars[3]
    Abar = pars[4]
    side = pars[5]
    kappa = pars[6]
    dkappa = pars[7]
    dclear = pars[8]
    X = y[0]
    Xd = y[1]
    w = y[2]
    wd = y[3]
    x0 = beta**2
    x1 = eps*x0
    x2 = x1 + 1
    x3 = wd*x2
    x4 = Xd*gamma
    x5 = gamma*wd
    x6 = Abar*numpy.cos(tau)
    x7 = eps*x2
    x8 = eps*sigma
    x9 = x8 - 1
    x10 = X*x9*(x0 - 1)
    x11 = w*x9*(eps + x0)
    x12 = x10 - x11
    x13 = x12 + x7*(eps*x5 + x4 - x6)
    x14 = (dclear*x13 + x3)**(-1.0)
    x15 = kappa + 1
    x16 = x14*x15*x3
    x17 = eps**2
    x18 = gamma*x17
    x19 = dclear*x16
    x20 = eps*x4
    x21 = eps*x6
    x22 = x2**(-1.0)
    x23 = dkappa*side
    x24 = kappa*wd
    x25 = gamma*x24
    x26 = X*dclear
    x27 = dclear*w
    x28 = x0*x26
    x29 = wd**2*x23
    x30 = x0*x27
    x31 = dclear*x17
    x32 = x0*x31
    out[0] = 1
    out[1] = 0
    out[2] = 0
    out[3] = 0
    out[4] = 0
    out[5] = 1
    out[6] = x16*x18
    out[7] = -x18*x19
    out[8] = 0
    out[9] = 0
    out[10] = -wd*x15/(dclear*(x10*x22 - x11*x22 + x17*x5 + x20 - x21) + wd) + 1
    out[11] = x19
    out[12] = 0
    out[13] = 0
    out[14] = -x14*(x12 + x13*(kappa + wd*x23) - x7*(eps*x25 - x4 + x6))
    out[15] = -x14*(dclear*eps**3*x0*x25 - dclear*x20 + dclear*x21 - eps*x27 + sigma*x17*x27 + x1*x24 + x1*x29 + x24 + x25*x31 + x26*x8 - x26 - x28*x8 + x28 + x29 + x30*x8 - x30 - x32*x4 + x32*x6)
    out[16] = -x24
