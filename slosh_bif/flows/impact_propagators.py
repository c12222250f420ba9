"""The propagators of the vibro-impact model (8) between impacts and their parameter derivatives.

Between impacts (8) is ``z' = K z`` on ``z = [X, X', w, w', cos tau, sin tau]``
(:meth:`~slosh_bif.model.equations.ImpactModel.augmented`); its flow over L is ``expm(K L)``, and
the derivative of that flow in a parameter of K is the lower-left block of
``expm([[K, 0], [K_p, K]] L)``. :mod:`slosh_bif.flows.impact_flow` tabulates both for the
sample step and its halvings.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.flows.compiled import jit
from slosh_bif.model.equations import impact_augmented
from slosh_bif.model.params import Params

__all__ = ["LINEAR_PARAMETERS", "WALL_PARAMETERS", "propagators", "derivative_of_K"]

LINEAR_PARAMETERS = ("eps", "beta", "gamma", "sigma", "Abar")
WALL_PARAMETERS = ("lam", "chi")  # enter only the restitution law (21)


def propagators(K, lengths):
    """``expm(K L)`` for the halving lengths L (longest first), by squaring up from the shortest:
    with ``expm(K L) = I + E``, ``E(2L) = 2 E(L) + E(L)**2`` keeps E's relative accuracy (the
    identity is never added in), so the 50 levels cost 50 small products instead of 50 expm."""
    A = np.ascontiguousarray(K * lengths[-1])
    E = A @ (
        np.eye(len(K)) + A @ (np.eye(len(K)) / 2 + A @ (np.eye(len(K)) / 6 + A / 24))
    )  # |A| < 1e-15: exact
    out = np.empty((len(lengths),) + K.shape)
    _square_up(np.ascontiguousarray(E), out)
    return out


@jit
def _square_up(E, out):
    """out[k] = I + E_k with E_{k-1} = 2 E_k + E_k**2 from E_last = E (compiled: a chart builds
    thousands of flows, each 50 products of 12 x 12 matrices)."""
    n = E.shape[0]
    last = out.shape[0] - 1
    current = E.copy()
    nxt = np.empty_like(E)
    for k in range(last, -1, -1):
        for i in range(n):
            for j in range(n):
                out[k, i, j] = current[i, j] + (1.0 if i == j else 0.0)
        if k == 0:
            break
        for i in range(n):
            for j in range(n):
                total = 0.0
                for m in range(n):
                    total += current[i, m] * current[m, j]
                nxt[i, j] = 2.0 * current[i, j] + total
        current[:, :] = nxt


def derivative_of_K(params: Params, param: str, exact: bool = False) -> np.ndarray:
    """dK/d param by a five-point central difference: K of (8), whose entries are polynomials of
    degree <= 4 in the parameters (exact up to rounding), or ``exact``, of (9)'s linear part,
    rational in eps (the difference's error, ~1e-12 of dK, is below the map's rounding)."""
    values = {name: float(getattr(params, name)) for name in LINEAR_PARAMETERS}
    step = 1e-3 * max(1.0, abs(values[param]))
    K = [impact_augmented(**{**values, param: values[param] + k * step}, exact=exact) for k in (-2, -1, 1, 2)]
    return (K[0] - 8 * K[1] + 8 * K[2] - K[3]) / (12 * step)
