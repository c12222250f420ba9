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
    x0 = Abar*eps*numpy.cos(tau)
    x1 = Xd*eps*gamma
    x2 = beta**2
    x3 = beta**4*eps
    x4 = eps*sigma
    x5 = x2*x4
    x6 = -x2 + x3 + x5
    x7 = eps*x2
    x8 = -X*(-x4 + x6 - x7 + 1) + w*(-eps + x6) + x0 - x1
    x9 = (-dclear*x8 + wd)**(-1.0)
    x10 = wd*x9*(kappa + 1)
    x11 = dkappa*side
    x12 = X*dclear
    x13 = dclear*w
    x14 = eps*x13
    x15 = dclear*x1
    x16 = x13*x2
    x17 = x12*x4
    x18 = x12*x2
    x19 = dclear*x0
    x20 = x12*x3
    x21 = x12*x7
    x22 = x13*x3
    x23 = x12*x5
    x24 = x13*x5
    x25 = kappa*wd
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
    out[10] = 1 - x10
    out[11] = dclear*x10
    out[12] = 0
    out[13] = 0
    out[14] = -x9*(-x8*(kappa + wd*x11) - x8)
    out[15] = -(wd**2*x11 - x12 - x14 - x15 - x16 + x17 + x18 + x19 - x20 + x21 + x22 - x23 + x24 + x25)/(wd + x12 + x14 + x15 + x16 - x17 - x18 - x19 + x20 - x21 - x22 + x23 - x24)
    out[16] = -x25
