"""The slow invariant manifold (SIM) of the 1:1 resonance, eqs. (31), (32), (36).

On the manifold the particle's relative motion is ``w0 = A sin(T0 + psi) + f`` with the triangle
wave ``f`` of amplitude ``alpha`` (eq. 29). The two impact conditions (31) and (32) with ``B = 0``,

    A cos(eta + psi) = rho * alpha,    A sin(eta + psi) = 1 - alpha,

give ``A**2 = (1 - alpha)**2 + (rho*alpha)**2``, whose two roots are the branches of (36):

    alpha(A) = (1 +/- sqrt((1 + rho**2) (A**2 - A_min**2))) / (1 + rho**2),
    A_min = rho / sqrt(1 + rho**2),    alpha_min = alpha(A_min) = 1 / (1 + rho**2).

The ``+`` branch is the stable branch S+, the ``-`` branch the unstable one; they meet at the
fold ``(A_min, alpha_min)``, below which no 1:1 resonant impact motion exists.
"""

from __future__ import annotations

import numpy as np

__all__ = ["a_min", "alpha_min", "alpha", "STABLE", "UNSTABLE"]

STABLE = +1
UNSTABLE = -1


def a_min(rho):
    """Smallest amplitude A of X with 1:1 resonant impacts, eq. (36)."""
    rho = np.asarray(rho, dtype=float)
    return rho / np.sqrt(1.0 + rho**2)


def alpha_min(rho):
    """Triangle-wave amplitude at the manifold's fold, ``1/(1 + rho**2)``."""
    rho = np.asarray(rho, dtype=float)
    return 1.0 / (1.0 + rho**2)


def alpha(A, rho, branch: int = STABLE):
    """Triangle-wave amplitude alpha on the SIM, eq. (36).

    Parameters
    ----------
    A : array_like
        Amplitude of X; must be >= A_min(rho) (checked).
    rho : array_like
        Impact parameter of eq. (31), broadcast against ``A``.
    branch : {+1, -1}
        ``STABLE`` (+1, the branch S+) or ``UNSTABLE`` (-1).

    Returns
    -------
    ndarray
        alpha, with the broadcast shape of ``A`` and ``rho``.
    """
    if branch not in (STABLE, UNSTABLE):
        raise ValueError(f"branch must be +1 (stable) or -1 (unstable); got {branch!r}")
    A = np.asarray(A, dtype=float)
    rho = np.asarray(rho, dtype=float)
    disc = (1.0 + rho**2) * A**2 - rho**2
    # A few ulps below zero at A = A_min is rounding, not a point off the manifold.
    tiny = 8 * np.finfo(float).eps * np.maximum(1.0, rho**2)
    if np.any(disc < -tiny) or np.any(~np.isfinite(disc)):
        bad = np.broadcast_to(A, disc.shape)[(disc < -tiny) | ~np.isfinite(disc)]
        raise ValueError(
            f"amplitude A must be >= A_min = rho/sqrt(1+rho**2) on the manifold; got A = {bad.ravel()[:5]}"
        )
    return (1.0 + branch * np.sqrt(np.maximum(disc, 0.0))) / (1.0 + rho**2)
