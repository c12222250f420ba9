"""The vessel's displacement X of the vibro-impact model (8) at a record's times, and its
derivatives, from a run of the exact flow (its samples and impacts, with the saltation
sensitivities there: :meth:`~slosh_bif.flows.impact.flow.ImpactFlow.sensitivities`). Between two
rows of a run (8) is linear, so from the last row before a time the flight's closed form
expm(K s) on the state with the forcing's (cos, sin) carries the state there, and its Frechet
derivative in K's parameter carries the sensitivity (eqs. 8, 39: flights between the impacts)."""

from __future__ import annotations

import numpy as np
from scipy import linalg

__all__ = ["Flights"]


class Flights:
    """From the run (``t``, ``y``) of ``flow`` to ``times`` (each at or after t[0]): the row each
    time's flight starts from, that row's augmented state and the flight's length."""

    def __init__(self, flow, t, y, times):
        self.flow = flow
        self.last = np.searchsorted(t, times, side="right") - 1  # the post-impact row where one sits
        tl = t[self.last]
        self.z = np.vstack([y[:, self.last], np.cos(tl), np.sin(tl)])  # (6, len(times))
        self.s = np.asarray(times, dtype=float) - tl

    def X(self) -> np.ndarray:
        """X at the times."""
        E = linalg.expm(self.flow.K[None] * self.s[:, None, None])  # (times, 6, 6), one batched call
        return np.einsum("nj,jn->n", E[:, 0, :], self.z)

    def derivative(self, dy, parameter: bool = True) -> np.ndarray:
        """dX at the times given ``dy`` (len(times), 4), the state's derivative at each time's row;
        with ``parameter`` the flight's own dependence on the flow's parameter added (the Frechet
        derivative F of expm(K s) along Kp s, the upper right block of expm([[K s, Kp s], [0, K s]]))."""
        K, h = self.flow.K, self.s[:, None, None]
        if not parameter:
            E = linalg.expm(K[None] * h)
            return np.einsum("ni,ni->n", E[:, 0, :4], dy)
        n = K.shape[0]
        block = np.zeros((len(self.s), 2 * n, 2 * n))
        block[:, :n, :n] = block[:, n:, n:] = K[None] * h
        block[:, :n, n:] = self.flow.Kp[None] * h
        B = linalg.expm(block)
        E, F = B[:, :n, :n], B[:, :n, n:]
        return np.einsum("ni,ni->n", E[:, 0, :4], dy) + np.einsum("nj,jn->n", F[:, 0, :], self.z)
