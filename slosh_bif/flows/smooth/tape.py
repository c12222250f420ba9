"""The second-order variational equations of (9) replayed on the kept steps of the shooting arcs
(:func:`~slosh_bif.flows.smooth.dop853.arcs_loop` with a tape), once the direction they are wanted
along is known.

The curve problems of :mod:`slosh_bif.orbits.codim2` need, at each Newton iterate, the derivatives
of the arc matrices Phi_k and of the sensitivities along the null vector v of the block-cyclic
matrix J_mu: the second-order variational equations

    d' = J d,   Psi' = J Psi + f_yy[d, Phi],   r' = J r + f_yy[d, s] + f_ya d     (d(0) = v_k)

(the generated along kernel). v is known only after the arcs themselves: J_mu is made of them.
So the arcs are integrated first with every accepted step kept (its time, size and the states of
the 29 shooting components its 13 stages were evaluated at), and the 28 components above are
then integrated on exactly those steps: each stage's shooting state read from the tape, the 28
advanced by the same Runge-Kutta weights. The result is the along kernel's integration
with its error norm over the first 29 (the derivatives ride on the orbit's steps) at the cost of
the 28 alone, where a second integration of all 57 would repeat the orbit's 29.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.flows.compiled import jit as _jit
from slosh_bif.flows.smooth.dop853 import _kernel, _kernel_call
from slosh_bif.flows.smooth.dop853_interface import EXTRA_SIZE as EXTRA
from slosh_bif.flows.smooth.dop853_interface import SHOOTING_SIZE, WHICH

__all__ = ["replay_loop"]

# the kernel numbers as the compiled loop reads them (plain integers: a dict is no numba constant)
_EXTRA_KERNEL, _SIGMA_ABAR_KERNEL = WHICH["along_extra"], WHICH["along_sigma_abar"]


@_jit
def _replay_loop(dedicated, tapes, counts, directions, pars, A, B, C):
    """The 28 along components of every arc, from d = ``directions[k]`` (and zeros), on the steps
    of ``tapes``: (m, 28) at the arcs' ends. ``dedicated``: the tape is the (sigma, Abar)
    shooting kernel's (else the pair kernel's, its weights in ``pars``)."""
    which = _SIGMA_ABAR_KERNEL if dedicated else _EXTRA_KERNEL
    m = counts.shape[0]
    n = SHOOTING_SIZE
    out = np.empty((m, EXTRA))
    KE = np.empty((13, EXTRA))
    stage = np.empty(n + EXTRA)
    e = np.empty(EXTRA)
    for k in range(m):
        for i in range(EXTRA):
            e[i] = 0.0
        for i in range(4):
            e[i] = directions[k, i]
        tape = tapes[k]
        for step in range(counts[k]):
            row = tape[step]
            t = row[0]
            hh = row[1]
            if step == 0:  # the first stage at the arc's start; later it is the last step's 13th
                for i in range(n):
                    stage[i] = row[2 + i]
                for i in range(EXTRA):
                    stage[n + i] = e[i]
                _kernel_call(which, t, stage, KE[0], pars)
            else:
                for i in range(EXTRA):
                    KE[0, i] = KE[12, i]
            for s in range(1, 13):
                weights = A[s] if s < 12 else B
                for i in range(n):
                    stage[i] = row[2 + n * s + i]
                for i in range(EXTRA):
                    stage[n + i] = 0.0
                for j in range(s):
                    a = weights[j]
                    if a != 0.0:
                        for i in range(EXTRA):
                            stage[n + i] += a * KE[j, i]
                for i in range(EXTRA):
                    stage[n + i] = e[i] + hh * stage[n + i]
                _kernel(which, t + (C[s] * hh if s < 12 else hh), stage, KE[s], pars)
            for i in range(EXTRA):
                e[i] = stage[n + i]  # the 12th combination, B's: the step's end
        for i in range(EXTRA):
            out[k, i] = e[i]
    return out


replay_loop = _replay_loop
