"""The impact of the vibro-impact model (8): its reset and saltation matrix, for the compiled flow (slosh_bif.flows.impact.flow).

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
    x0 = eps**2
    x1 = gamma*x0
    x2 = X*dclear
    x3 = eps*w
    x4 = dclear*x3
    x5 = Xd*gamma
    x6 = eps*x5
    x7 = dclear*x6
    x8 = beta**2
    x9 = w*x8
    x10 = dclear*x9
    x11 = eps*x8
    x12 = wd*x11
    x13 = eps*sigma
    x14 = x13*x2
    x15 = x2*x8
    x16 = Abar*numpy.cos(tau)
    x17 = eps*x16
    x18 = dclear*x17
    x19 = dclear*wd
    x20 = x1*x19
    x21 = sigma*w
    x22 = x0*x21
    x23 = dclear*x22
    x24 = sigma*x11
    x25 = x2*x24
    x26 = x11*x21
    x27 = dclear*x26
    x28 = x0*x8
    x29 = x28*x5
    x30 = dclear*x29
    x31 = eps**3*gamma*x8
    x32 = x19*x31
    x33 = x16*x28
    x34 = dclear*x33
    x35 = (wd + x10 + x12 - x14 - x15 - x18 + x2 + x20 - x23 + x25 - x27 + x30 + x32 - x34 + x4 + x7)**(-1.0)
    x36 = kappa*x11
    x37 = x35*(kappa + x11 + x36 + 1)
    x38 = kappa*wd
    x39 = -x10 + x11*x38 + x14 + x15 + x18 - x2 + x23 - x25 + x27 - x30 + x34 + x38 - x4 - x7
    x40 = X*kappa
    x41 = X*x13
    x42 = dkappa*side
    x43 = wd*x42
    x44 = X*x8
    x45 = wd**2*x42
    x46 = x12*x42
    x47 = dclear*x38
    out[0] = 1
    out[1] = 0
    out[2] = 0
    out[3] = 0
    out[4] = 0
    out[5] = 1
    out[6] = wd*x1*x37
    out[7] = -x20*x37
    out[8] = 0
    out[9] = 0
    out[10] = -x35*(-x20 - x32 + x39)
    out[11] = x19*x37
    out[12] = 0
    out[13] = 0
    out[14] = -x35*(X*sigma*x46 + X*x24 + X*x43 + X - kappa*x17 - kappa*x22 + kappa*x29 + kappa*x3 - kappa*x33 + kappa*x6 + kappa*x9 + x1*x45 - x13*x40 - x17*x43 - x17 - x21*x36 - x21*x46 - x22*x43 - x22 + x24*x40 - x26 + x29*x43 + x29 + x3*x43 + x3 + x31*x45 - x33*x43 - x33 - x40*x8 + x40 - x41*x43 - x41 - x43*x44 + x43*x6 + x43*x9 - x44 + x6 + x9)
    out[15] = -x35*(x1*x47 + x11*x45 + x31*x47 + x39 + x45)
    out[16] = -x38


def impact_reset_jet_kernel(tau, y, out, pars):
    """out = [w'+, dw'+/dw'-, d2 w'+/dw'-2, d3 w'+/dw'-3] of an impact of (8) on either wall (eqs. 2, 21); y is the state before it, pars = (loss, q)."""
    loss = pars[0]
    q = pars[1]
    X = y[0]
    Xd = y[1]
    w = y[2]
    wd = y[3]
    x0 = loss - 1
    x1 = -x0
    x2 = numpy.sqrt(x1)
    x3 = x2**(-1.0)
    x4 = loss*q
    x5 = 2*loss
    x6 = loss**2
    x7 = q**2
    out[0] = -wd*x2
    out[1] = x3*(x0 + (1/2)*x4)
    out[2] = -1/4*x4*(-2*q + x4 + x5 - 2)/(wd*x1**(3/2))
    out[3] = (1/8)*x3*x4*(8*loss - x5*x7 + x6*x7 - 4*x6 + 4*x7 - 4)/(wd**2*(-x5 + x6 + 1))
