"""The first harmonic A1 of a 2pi-orbit of (9) and its derivatives in the parameters, from the
variational equations (the pair kernel of the shooting code) rather than differences of orbits.

A 2pi-orbit y(tau; y0, q) of (9) with y(2pi) = y0 moves with the parameters q as
(M - I) dy0/dq = -s(2pi), where M is the monodromy matrix and s the solution's sensitivity at
fixed start; along it dy(tau)/dq = Phi(tau) dy0/dq + s(tau). A1 = |c1| with c1 the forcing
frequency's Fourier coefficient of X (eq. 25's amplitude A, which the slow flow approximates),
by the trapezoid rule on a uniform grid (spectrally accurate for a smooth periodic X), so
dA1/dq = Re(conj(c1) dc1/dq) / A1 with dc1/dq the same rule applied to dX/dq. One integration
of the 29-component system gives the derivatives along two directions in the parameters.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.flows.smooth import integrator
from slosh_bif.model.params import REAL_FIELDS, Params

__all__ = ["first_harmonic_gradient", "POINTS"]

POINTS = 512  # grid points per period, as the orbits' measures (orbit_tools.orbit_measures)


def first_harmonic_gradient(
    params: Params, y0, directions, *, points: int = POINTS, rtol: float = 1e-10, backend: str = "auto"
):
    """(A1, dA1) of the 2pi-orbit of (9) through ``y0`` at ``params``: ``directions`` is a list of
    dicts, each mapping names of ``REAL_FIELDS`` to weights (a direction in the parameters), and
    dA1[j] is A1's derivative along direction j, the orbit moving with it (y0 a converged orbit:
    Newton's residual sets the derivatives' accuracy). ValueError when M - I is singular to
    rounding (a fold of the orbits, where A1 has no derivative along the family)."""
    rows = []
    for direction in directions:
        unknown = set(direction) - set(REAL_FIELDS)
        if unknown:
            raise ValueError(
                f"directions name {', '.join(sorted(unknown))}; they take {', '.join(REAL_FIELDS)}"
            )
        rows.append([float(direction.get(name, 0.0)) for name in REAL_FIELDS])
    if len(rows) % 2:
        rows.append([0.0] * len(REAL_FIELDS))  # the pair kernel takes two at a time
    taus = np.linspace(0.0, 2 * np.pi, points + 1)
    harmonic = np.exp(-1j * taus[:-1]) * 2 / points  # the rfft's bin 1, scaled to an amplitude
    A1, dA1 = None, []
    for k in range(0, len(rows), 2):
        z = integrator.integrate_grid(
            params, y0, taus, rtol=rtol, atol=rtol * 1e-2, backend=backend, directions=rows[k : k + 2]
        )
        Phi = z[:, 4:20].reshape(-1, 4, 4)
        S = z[:, 20:28].reshape(-1, 2, 4).transpose(0, 2, 1)  # (tau, component, direction)
        lhs = Phi[-1] - np.eye(4)
        if np.linalg.cond(lhs) > 1e12:
            raise ValueError("the orbit's monodromy has a multiplier 1: A1 has no derivative here (a fold)")
        dy0 = np.linalg.solve(lhs, -S[-1])  # (component, direction)
        dX = Phi[:-1, 0, :] @ dy0 + S[:-1, 0, :]  # (tau, direction)
        c1 = complex(z[:-1, 0] @ harmonic)
        A1 = abs(c1)
        dc1 = harmonic @ dX
        dA1.extend((np.conj(c1) * dc1).real / A1)
    return A1, np.array(dA1[: len(directions)])
