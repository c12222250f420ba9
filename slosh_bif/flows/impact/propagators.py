"""The propagators of the vibro-impact model (8) between impacts and their parameter derivatives.

Between impacts (8) is ``z' = K z`` on ``z = [X, X', w, w', cos tau, sin tau]``
(:meth:`~slosh_bif.model.equations.ImpactModel.augmented`); its flow over L is ``expm(K L)``, and
the derivative of that flow in a parameter of K is the lower-left block of
``expm([[K, 0], [K_p, K]] L)``. :mod:`slosh_bif.flows.impact.flow` tabulates both for the
sample step and its halvings.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.flows.compiled import jit
from slosh_bif.model._generated import models as gen
from slosh_bif.model.params import Params

__all__ = ["LINEAR_PARAMETERS", "WALL_PARAMETERS", "propagators", "derivative_of_K"]

LINEAR_PARAMETERS = ("eps", "beta", "gamma", "sigma", "Abar")
WALL_PARAMETERS = ("lam", "chi")  # enter only the restitution law (21)


def propagators(K, lengths, Kp=None):
    """``(table, dtable)``: ``expm(K L)`` for the halving lengths L (longest first), and with
    ``Kp = dK/d param`` its derivative in the parameter, the lower-left block of
    ``expm([[K, 0], [Kp, K]] L)`` (zeros without). Squared up from the shortest length: with
    ``expm(K L) = I + E`` and the derivative Q, ``E(2L) = 2 E + E**2`` and ``Q(2L) = 2 Q + Q E + E Q``
    keep their relative accuracy (the identity is never added in), so the 50 levels cost a few small
    products each instead of an expm."""
    K = np.ascontiguousarray(K, dtype=float)
    n = len(K)
    table = np.empty((len(lengths), n, n))
    dtable = np.zeros_like(table)
    derivative = Kp is not None
    Kp = np.ascontiguousarray(Kp, dtype=float) if derivative else np.zeros_like(K)
    _tables(K, Kp, float(lengths[-1]), derivative, table, dtable)
    return table, dtable


@jit
def _mul(A, B, out):
    n = A.shape[0]
    for i in range(n):
        for j in range(n):
            total = 0.0
            for m in range(n):
                total += A[i, m] * B[m, j]
            out[i, j] = total


@jit
def _mul_upper(A, B, out):
    """``out = A B`` for 6 x 6 matrices whose lower-left 2 x 4 block is zero, as the product's is
    (the flight's: the forcing's phase (cos tau, sin tau) is driven by nothing else)."""
    for i in range(6):
        lo = 4 if i >= 4 else 0
        for j in range(6):
            total = 0.0
            for m in range(lo, 4 if j < 4 else 6):
                total += A[i, m] * B[m, j]
            out[i, j] = total


@jit
def _tables(K, Kp, L, derivative, table, dtable):
    """The squaring of :func:`propagators`, compiled (a chart builds thousands of flows)."""
    n = K.shape[0]
    A = K * L
    B = Kp * L
    AA = np.empty((n, n))
    AAA = np.empty((n, n))
    _mul(A, A, AA)
    _mul(AA, A, AAA)
    E = A + AA / 2.0 + AAA / 6.0  # |A| < 1e-15: the next term is below rounding
    Q = np.zeros((n, n))
    if derivative:
        BA = np.empty((n, n))
        AB = np.empty((n, n))
        t1 = np.empty((n, n))
        t2 = np.empty((n, n))
        t3 = np.empty((n, n))
        _mul(B, A, BA)
        _mul(A, B, AB)
        _mul(BA, A, t1)
        _mul(A, BA, t2)
        _mul(AA, B, t3)
        Q = B + (BA + AB) / 2.0 + (t1 + t2 + t3) / 6.0
    EE = np.empty((n, n))
    QE = np.empty((n, n))
    EQ = np.empty((n, n))
    last = table.shape[0] - 1
    for k in range(last, -1, -1):
        for i in range(n):
            for j in range(n):
                table[k, i, j] = E[i, j] + (1.0 if i == j else 0.0)
                dtable[k, i, j] = Q[i, j]
        if k == 0:
            break
        _mul_upper(E, E, EE)
        if derivative:
            _mul_upper(Q, E, QE)
            _mul_upper(E, Q, EQ)
            Q = 2.0 * Q + QE + EQ
        E = 2.0 * E + EE


def derivative_of_K(params: Params, param: str, exact: bool = False) -> np.ndarray:
    """dK/d param of K of (8) (or, ``exact``, of (9)'s linear part: the corrected impact model's
    flights), from the derivation's generated derivatives: exact, no differences."""
    values = [float(getattr(params, name)) for name in LINEAR_PARAMETERS]
    stacked = (gen.flight_linear_derivatives if exact else gen.impact_linear_derivatives)(*values)
    block = stacked.reshape(len(LINEAR_PARAMETERS), 4, 5)[LINEAR_PARAMETERS.index(param)]
    Kp = np.zeros((6, 6))
    Kp[:4, :5] = block
    return Kp
