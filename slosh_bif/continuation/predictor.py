"""The continuation's predictor: the guess for the next point of the curve F(u) = 0 at arclength s
from the last one, as a function of s.

The corrector converges quadratically, so each order the guess gains saves evaluations of F (for
shooting, integrations of the variational equations): from the Fig. 10 branch's median guess
error of 3e-4 with the second-order guess to 6e-5 with the cubic, about half of the corrections
end after two evaluations instead of three.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["predictor", "hermite"]


def predictor(points, bend, h, opts):
    """The guess at arclength s from the last point a, as a function of s (the step's point is
    ``predict(h)``; a special point between is located along the same curve of guesses).

    Third order where it can be: the cubic through the last two points with their tangents,
    extrapolated (when the last two points lie between h / 4 and 4 h apart: a nearer one, a
    located special point say, would amplify its own error). Otherwise second order: the tangent
    plus half the turn over the last step (``bend``, trusted while it moves the guess by < h / 2),
    or the tangent alone."""
    a = points[-1]
    if opts.curved_predictor and len(points) > 1:
        prev = points[-2]
        # the arclength between them from the chord and the turn of the tangent (exact on a
        # circle; the chord alone would leave the guess second order)
        turn = math.acos(min(1.0, float(prev.t @ a.t)))
        span = float(np.linalg.norm(a.u - prev.u)) * (
            1.0 if turn < 1e-8 else 0.5 * turn / math.sin(0.5 * turn)
        )
        if 0.25 * h <= span <= 4.0 * h and turn < 1.0:
            return lambda s: hermite(prev, a, span, s)
    if bend is None or 0.5 * h * float(np.linalg.norm(bend)) >= 0.5:
        return lambda s: a.u + s * a.t
    return lambda s: a.u + s * a.t + (0.5 * s * s) * bend


def hermite(prev, a, span, s):
    """The cubic Hermite curve through prev (at -span) and a (at 0) with their unit tangents, at s."""
    x = 1.0 + s / span
    x2, x3 = x * x, x * x * x
    return (
        (2 * x3 - 3 * x2 + 1) * prev.u
        + (x3 - 2 * x2 + x) * span * prev.t
        + (3 * x2 - 2 * x3) * a.u
        + (x3 - x2) * span * a.t
    )
