"""The arcs of multiple shooting of (9) as a shooting problem keeps them: one integration of every
arc per (x, parameters), cached, serving the residual, Jacobian, sensitivities, multipliers and
Liouville's check of :class:`~slosh_bif.orbits.shooting.ShootingProblem`; and the arcs'
derivatives along a direction of their start states (the second-order variational equations),
which the curves of orbit bifurcations read g's derivatives from
(:mod:`slosh_bif.orbits.codim2.minaug`), replayed on the arcs' kept steps
(:mod:`slosh_bif.flows.smooth.arcs`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.flows.smooth import integrator
from slosh_bif.flows.smooth.arcs import EXTRA_SIZE, Tape, integrate_arcs, replay_along
from slosh_bif.model.params import Params

__all__ = ["Arcs", "ShootingArcs", "ARC_MAX_STEPS"]


@dataclasses.dataclass(frozen=True)
class Arcs:
    """One integration of every arc of multiple shooting from one (x, params).

    ends : (m, 4) arc end states;  mats : (m, 4, 4) arc matrices Phi_k;  sens : (m, 4, 2)
    d(end)/d(the problem's ``sensitivities``, in order);  trace : the integral of tr J over the period
    (Liouville);
    monodromy : Phi_{m-1} ... Phi_0.
    """

    ends: np.ndarray
    mats: np.ndarray
    sens: np.ndarray
    trace: float
    monodromy: np.ndarray


ARC_MAX_STEPS = 100_000
"""Steps one shooting arc may take. An orbit of the presets takes a few hundred a period; a Newton
iterate deep in the n = 50 wall shrinks the steps without bound. Past the limit the arc fails,
the evaluation's residual is NaN, and the corrector halves its step."""


class ShootingArcs:
    """The arcs of a shooting problem; the problem sets ``segments``, ``rtol``, ``atol``,
    ``backend``, ``sensitivities``, ``_taus``, ``evaluations``, the empty ``_cache``, and
    ``_tape = _taped = None`` (:class:`~slosh_bif.orbits.shooting.ShootingProblem`)."""

    def arcs(self, x, params: Params) -> "Arcs":
        """Integrate every arc from x at ``params`` (any parameter set, not only ``params_at(p)``):
        ends, arc matrices, the sensitivities in sigma and Abar, and the Liouville integral.
        Cached on x and *all* parameters, so a caller that changes any parameter gets fresh arcs.
        After :meth:`record_steps`, the steps are kept for :meth:`arcs_along`."""
        key = (x.tobytes(), params)
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        z, done = integrate_arcs(
            params,
            x.reshape(self.segments, 4),
            self._taus,
            rtol=self.rtol,
            atol=self.atol,
            backend=self.backend,
            sensitivities=self.sensitivities,
            max_steps=ARC_MAX_STEPS,
            tape=self._tape,
        )
        self.evaluations += done
        if self._tape is not None:  # the steps it keeps are these arcs' (if they all succeeded)
            self._taped = key if self._tape.counts is not None else None
        result = self._arcs_from(z)
        self._keep(key, result)
        return result

    def record_steps(self):
        """From now on the arcs keep their steps (on the compiled path), so that :meth:`arcs_along`
        replays the derivatives on them instead of integrating the arcs again: for the curve
        problems, which ask for derivatives at every point they evaluate."""
        if self._tape is None:
            self._tape = Tape()

    def _arcs_from(self, z):
        """The :class:`Arcs` of the shooting system's ends z (m, 29)."""
        m = self.segments
        mats = z[:, 4:20].reshape(m, 4, 4)
        ends = z[:, :4] if np.isfinite(z).all() else np.full((m, 4), np.nan)  # a failed arc: no residual
        M = mats[0]
        for Phi in mats[1:]:
            M = Phi @ M
        return Arcs(ends, mats, z[:, 20:28].reshape(m, 2, 4).transpose(0, 2, 1), float(z[:, 28].sum()), M)

    def arcs_along(self, x, params: Params, direction):
        """(arcs, Psi, R): :meth:`arcs` with the derivatives of the arc matrices (Psi, (m, 4, 4))
        and of the sensitivities (R, (m, 4, 2)) along ``direction`` of the arcs' start states x:
        the second-order variational equations, replayed on the arcs' kept steps on the compiled
        path (the arcs integrated again with their steps kept where they were not, and from then
        on kept: :meth:`record_steps`), else integrated with the arcs (the along kernel)."""
        direction = np.asarray(direction, dtype=float)
        m, key = self.segments, (x.tobytes(), params)
        if integrator.resolve_backend(self.backend) == "numba":
            if self._taped != key:  # the tape holds other arcs' steps (or none): integrate these again
                self.record_steps()
                self._cache.pop(key, None)
            arcs = self.arcs(x, params)
            if self._taped != key:  # a failed arc: no derivatives
                extra = np.full((m, EXTRA_SIZE), np.nan)
            else:
                extra = replay_along(self._tape, direction.reshape(m, 4))
        else:
            z, done = integrate_arcs(
                params,
                x.reshape(m, 4),
                self._taus,
                rtol=self.rtol,
                atol=self.atol,
                backend=self.backend,
                sensitivities=self.sensitivities,
                max_steps=ARC_MAX_STEPS,
                directions=direction.reshape(m, 4),
            )
            self.evaluations += done
            arcs = self._cache.get(key) or self._arcs_from(z[:, : integrator.SHOOTING_SIZE])
            self._keep(key, arcs)
            extra = z[:, integrator.SHOOTING_SIZE :]
        return arcs, extra[:, 4:20].reshape(m, 4, 4), extra[:, 20:28].reshape(m, 2, 4).transpose(0, 2, 1)

    def _keep(self, key, result):
        if len(self._cache) > 8:
            self._cache.clear()
        self._cache[key] = result
