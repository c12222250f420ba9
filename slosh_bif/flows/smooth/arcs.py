"""The arcs of multiple shooting of (9): the shooting system (the orbit, its arc matrices, two
parameter sensitivities and the Liouville integral) over every arc in one call, and the arcs'
derivatives along a direction of their start states (the second-order variational equations of
the generated along kernel), which the curves of orbit bifurcations need
(:mod:`slosh_bif.orbits.codim2.minaug`).

On the compiled path the derivatives are replayed on the recorded steps of the arcs
(:mod:`slosh_bif.flows.smooth.tape`): :func:`integrate_arcs` keeps them in a :class:`Tape`,
:func:`replay_along` gives the derivatives along any direction from it. On the scipy
path :func:`integrate_arcs` with ``directions`` integrates all 57 components with the error norm
of the first 29, to the same effect.
"""

from __future__ import annotations

import math

import numpy as np

from slosh_bif.flows.loops import compiled
from slosh_bif.flows.smooth.dop853_interface import ALONG_SIZE, EXTRA_SIZE, TABLEAU, TAPE_WIDTH, WHICH
from slosh_bif.flows.smooth.integrator import (
    DEFAULT_SENSITIVITIES,
    SHOOTING_SIZE,
    Integration,
    integrate,
    kernel_parameters,
    resolve_backend,
    scipy_rhs,
)
from slosh_bif.model.params import Params, real_pair

__all__ = ["integrate_arcs", "replay_along", "Tape", "ALONG_SIZE", "EXTRA_SIZE"]


class Tape:
    """Where the arcs' accepted steps are kept: a buffer reused from call to call (one a problem),
    grown where an arc takes more steps than it holds. After :func:`integrate_arcs` filled it,
    ``counts`` holds each arc's steps and ``pars`` the kernel parameters (``counts`` None: the
    last call failed and kept nothing usable)."""

    def __init__(self, rows_per_arc: int = 256):
        self.rows = np.empty((0, max(int(rows_per_arc), 1), TAPE_WIDTH))
        self.counts = None
        self.pars = None
        self.dedicated = False  # kept by the (sigma, Abar) shooting kernel (else the pair kernel)

    def _room(self, m: int, rows: int):
        if self.rows.shape[0] != m or self.rows.shape[1] < rows:
            self.rows = np.empty((m, max(rows, self.rows.shape[1]), TAPE_WIDTH))


def _kernel_choice(params, sensitivities, along):
    pair = along or tuple(sensitivities) != DEFAULT_SENSITIVITIES
    which = "along" if along else ("pair" if pair else "shooting")
    return which, kernel_parameters(params, None, real_pair(sensitivities, "sensitivities") if pair else None)


def integrate_arcs(
    params: Params,
    starts,
    taus,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    backend: str = "auto",
    sensitivities: tuple = DEFAULT_SENSITIVITIES,
    max_steps: int = 2_000_000,
    directions=None,
    tape: Tape | None = None,
):
    """The shooting system over every arc of multiple shooting: arc k from ``starts[k]`` (with
    Phi = I and zero sensitivities) over [taus[k], taus[k + 1]]. Returns (ends (m, 29), arcs
    integrated); rows of the arcs after a failed one are NaN. The compiled backend runs all arcs
    in one call; otherwise :func:`integrate` arc by arc.

    ``tape`` (compiled path): the accepted steps are kept in it, and the derivatives along any
    direction then follow by :func:`replay_along`.
    ``directions`` (m, 4), on either path: the ends (m, 57) with those derivatives, all 57
    integrated at once (``ALONG_SIZE``; the first 29 those of the pair kernel: the derivatives ride
    on the steps those choose, on the scipy path through an error norm weighted to the same
    effect)."""
    starts = np.ascontiguousarray(starts, dtype=float)
    m = len(starts)
    along = directions is not None
    size = ALONG_SIZE if along else SHOOTING_SIZE
    if along:
        directions = np.ascontiguousarray(directions, dtype=float).reshape(m, 4)
    numba = resolve_backend(backend) == "numba" and np.isfinite(starts).all()
    which, pars = _kernel_choice(params, sensitivities, along)
    if tape is not None:
        tape.counts = None
    if numba and tape is not None and not along:
        return _taped(tape, which, pars, starts, taus, rtol, atol, max_steps)
    if numba:
        return _arcs(which, pars, starts, directions if along else starts, taus, rtol, atol, max_steps)[:2]
    ends = np.full((m, size), np.nan)
    for k in range(m):
        if not np.all(np.isfinite(starts[k])):
            return ends, k
        z0 = np.zeros(size)
        z0[:4], z0[4:20] = starts[k], np.eye(4).ravel()
        if along:
            z0[SHOOTING_SIZE : SHOOTING_SIZE + 4] = directions[k]
            run = _scipy_along(pars, z0, (taus[k], taus[k + 1]), rtol, atol)
        else:
            run = integrate(
                params,
                z0,
                (taus[k], taus[k + 1]),
                shooting=True,
                rtol=rtol,
                atol=atol,
                backend=backend,
                sensitivities=sensitivities,
                max_steps=max_steps,
            )
        if not (run.success and np.all(np.isfinite(run.z))):
            return ends, k + 1
        ends[k] = run.z
    return ends, m


def _arcs(which, pars, starts, directions, taus, rtol, atol, max_steps, rows=None):
    """The compiled arcs loop: (ends, arcs integrated, status, steps per arc), the steps kept in
    ``rows`` (m, capacity, width) where given (``directions`` is read by the along kernel alone)."""
    m = len(starts)
    ends, done, status, counts = compiled().arcs_loop(
        WHICH[which],
        np.ascontiguousarray(taus, dtype=float),
        starts,
        directions,
        pars,
        float(rtol),
        float(atol),
        int(max_steps),
        np.empty((m, 0, 1)) if rows is None else rows,
        *TABLEAU,
    )
    return ends, min(done + 1, m), status, counts


def _taped(tape: Tape, which, pars, starts, taus, rtol, atol, max_steps):
    """The arcs with their steps kept in ``tape``; integrated again with room for every step where
    an arc took more than the tape held."""
    m = len(starts)
    tape._room(m, 0)
    while True:
        ends, done, status, counts = _arcs(
            which, pars, starts, starts, taus, rtol, atol, max_steps, tape.rows
        )
        if status != 0 or counts.max() <= tape.rows.shape[1]:
            tape.counts, tape.pars = (counts, pars) if status == 0 else (None, None)
            tape.dedicated = which == "shooting"
            return ends, done
        tape._room(m, int(1.25 * counts.max()) + 16)


def replay_along(tape: Tape, directions):
    """The arcs' derivatives along ``directions`` (m, 4) of their start states, replayed on the
    steps ``tape`` kept (of the last :func:`integrate_arcs` that filled it): (m, 28) = [d, D Phi . d
    (row-major), D dy/da . d, D dy/db . d] at the arcs' ends."""
    if tape.counts is None:
        raise ValueError("the tape keeps no steps: the arcs that filled it failed, or none did")
    directions = np.ascontiguousarray(directions, dtype=float).reshape(len(tape.counts), 4)
    A, B, C = TABLEAU[:3]
    return compiled().replay_loop(tape.dedicated, tape.rows, tape.counts, directions, tape.pars, A, B, C)


def _scipy_along(pars, z0, span, rtol, atol) -> Integration:
    """The along kernel by scipy's DOP853, its error norm over the first 29 components as the
    compiled loop's: the rest carry an infinite atol, the first 29 their tolerances times
    sqrt(29 / 57) (scipy's norm is a mean over every component)."""
    from scipy.integrate import solve_ivp  # the fallback only

    factor = math.sqrt(SHOOTING_SIZE / ALONG_SIZE)
    atols = np.full(ALONG_SIZE, np.inf)
    atols[:SHOOTING_SIZE] = atol * factor
    with np.errstate(over="ignore", invalid="ignore"):
        sol = solve_ivp(scipy_rhs("along", pars), span, z0, method="DOP853", rtol=rtol * factor, atol=atols)
    return Integration(
        sol.y[:, -1].copy(), len(sol.t) - 1, 0, int(sol.nfev), math.nan, bool(sol.success), str(sol.message)
    )
