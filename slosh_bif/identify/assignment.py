"""Which response a measured point is compared with: every stable response of the fitted model
at the point's sigma (the stable steady states of (46), or the stable 2pi-orbits of (9) or (8))
is a candidate, and the point takes the one that explains it best. Least squares over the
assignment: the residuals are separable, so each point's nearest candidate minimises the sum.

A sweep label is evidence, not a constraint: the candidate that continues the sweep (nearest the
amplitude its last point took: an up-sweep past a fold stays on its branch) is kept while it
explains the point within :data:`TIE` standard deviations of the best candidate; otherwise the
point takes the best, whichever sweep it was measured in. An up- and a down-sweep at the same
sigma may so land on the same response or on two.
"""

from __future__ import annotations

import numpy as np

__all__ = ["TIE", "TIE_RELATIVE", "UNEXPLAINED", "tie", "pick", "unexplained", "with_followed"]

TIE = 2.0  # standard deviations within which a sweep's continuing candidate is preferred
TIE_RELATIVE = 0.02  # without a std: the tie as a fraction of the data's largest amplitude
UNEXPLAINED = 3.0  # a point farther than this many standard deviations from every candidate


def tie(data, i: int) -> float:
    """How much worse than the best candidate a sweep's continuing one may fit point i."""
    if data.std is not None:
        return TIE * float(data.std[i])
    return TIE_RELATIVE * float(np.max(np.abs(data.A)))


def pick(data, i: int, previous_A, candidates) -> int:
    """The index in ``candidates`` (each ``(A, stable, ...)``) that point i of ``data`` takes: the
    stable ones (all where none is stable), nearest the point's amplitude, or the one nearest
    ``previous_A`` (the amplitude the point's sweep took last; None: not in a sweep, or its first
    point) while that one fits within :func:`tie` of the nearest."""
    if not candidates:
        raise ValueError("no candidate response to compare the point with")
    pool = [k for k, c in enumerate(candidates) if c[1]] or list(range(len(candidates)))
    A = float(data.A[i])
    best = min(pool, key=lambda k: abs(candidates[k][0] - A))
    if previous_A is None:
        return best
    cont = min(pool, key=lambda k: abs(candidates[k][0] - previous_A))
    if abs(candidates[cont][0] - A) <= abs(candidates[best][0] - A) + tie(data, i):
        return cont
    return best


def unexplained(data, stable_amplitudes, scale: float | None = None) -> list:
    """The indices of the points that no stable response explains: farther than
    :data:`UNEXPLAINED` standard deviations (``data.std``, else ``scale``) from every amplitude of
    ``stable_amplitudes[i]`` (an empty list: no stable response at that sigma at all)."""
    out = []
    for i, amplitudes in enumerate(stable_amplitudes):
        spread = float(data.std[i]) if data.std is not None else scale
        if not amplitudes:
            out.append(i)
        elif spread is not None and spread > 0:
            if min(abs(float(data.A[i]) - a) for a in amplitudes) > UNEXPLAINED * spread:
                out.append(i)
    return out


def with_followed(stable_amplitudes, followed_A, followed_stable) -> list:
    """Each point's stable amplitudes (``stable_amplitudes[i]``, found by a search at the estimate)
    with the amplitude ``followed_A[i]`` of the orbit the fit followed there added where that orbit
    is stable (``followed_stable[i]``) and not among them: a search afresh can miss a stable orbit
    that the fit, following it from the start, holds, and the point is explained by it all the
    same."""
    out = []
    for amplitudes, a, ok in zip(stable_amplitudes, followed_A, followed_stable):
        known = [float(b) for b in amplitudes]
        if ok and all(abs(b - float(a)) > 1e-9 * (1.0 + abs(b)) for b in known):
            known = sorted(known + [float(a)])
        out.append(known)
    return out
