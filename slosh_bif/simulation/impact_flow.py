"""The exact flow of the vibro-impact model (8), compiled: flights in closed form, every impact found
with a certificate, and the restitution law (2), (21) applied at each.

Flights. Between impacts (8) is linear with constant coefficients; on ``z = [X, X', w, w', cos tau,
sin tau]`` it is ``z' = K z`` (:meth:`~slosh_bif.model.equations.ImpactModel.augmented`), whose flow
over s is ``expm(K s)``. The propagators ``P_k = expm(K h 2**-k)``, k = 0..LEVELS, are made once per
parameter set and sample step h; products of them give the state at any dyadic point of a step
exactly up to rounding. There is no integration error, no expm in the loop, and no special case at
resonance or for the Jordan block that (8) has at beta = 0 (where a modal solution breaks down).

Impacts with a certificate. On an interval of length L where ``f = +-w`` has the values f0, f1 and
slopes d0, d1 at its ends and ``|f''| <= B`` (``w'' = K[3] . z`` and ``|z(s)| <= exp(|K| s) |z(0)|``
in the max-norm), f lies below both parabolas ``f0 + d0 s + B s**2/2`` and ``f1 - d1 (L - s) +
B (L - s)**2/2``. Their lower envelope is convex on each side of the single point where they meet,
so if it is below the wall there and at s = L, f cannot reach the wall inside: the interval is free.
An interval that is not free is halved, the left half first, so the first impact is found however
fast or however grazing the approach; at the finest level (L = h 2**-LEVELS, 1e-16 of tau at the
default step) an interval whose end lies at or beyond the wall holds the impact, and one whose end
does not is a tangency within rounding, not an impact.

Impacts. ``w'+ = -kappa(|w'-|) w'-`` with kappa of (21), ``sqrt(1 - c v**q)``. A run stops with a
status rather than going on without a model: ``"kappa-not-real"`` where (21) gives no real kappa,
``"sticking"`` where the post-impact speed falls below ``stick_speed`` (impacts then accumulate at a
point in time, beyond which (8) without a sticking phase is not defined), ``"max-impacts"``.

:func:`slosh_bif.simulation.vibro_impact.simulate_impact` is the entry point; its event loop on
``scipy.linalg.expm`` is the reference this flow is tested against.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import linalg

from slosh_bif.model.equations import ImpactModel
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import dissipation_at_unit_speed
from slosh_bif.simulation.compiled import jit

__all__ = ["LEVELS", "ImpactFlow"]

LEVELS = 48  # the finest interval is h 2**-48
# Codes of the compiled run.
_FINISHED, _STICKING, _KAPPA_NOT_REAL, _MAX_IMPACTS, _FULL = 0, 1, 2, 3, 4


@jit(inline=True)
def _apply(P, z, out):
    for i in range(6):
        acc = 0.0
        for j in range(6):
            acc += P[i, j] * z[j]
        out[i] = acc


@jit(inline=True)
def _may_reach(f0, d0, f1, d1, L, B):
    """Whether f may reach 1 in (0, L]: f(0) = f0 <= 1 (1 only when leaving the wall, d0 < 0),
    f(L) = f1, slopes d0, d1, |f''| <= B."""
    if f1 >= 1.0 or (f0 >= 1.0 and d0 >= 0.0):
        return True
    denom = d0 - d1 + B * L  # >= 0, as |d1 - d0| <= B L
    if denom <= 0.0:
        return max(f0, f1) + 0.125 * B * L * L >= 1.0  # the linear interpolant's bound
    s = -(f0 - f1 + d1 * L - 0.5 * B * L * L) / denom  # where the two parabolas meet
    if s <= 0.0 or s >= L:
        return False  # the envelope is one convex parabola, below 1 at s = L and at most 1 at s = 0
    return f0 + d0 * s + 0.5 * B * s * s >= 1.0


@jit(inline=True)
def _max_abs(z):
    m = 0.0
    for i in range(6):
        m = max(m, abs(z[i]))
    return m


@jit
def _piece(table, lengths, growth, row_norm, z, k0, out, stack_z, stack_k, stack_s):
    """Advance ``z`` over one dyadic piece of length ``lengths[k0]``, or to the first impact in it.

    Returns ``(side, s)``: side 0 and s the piece's length when it is free (``out`` is the end
    state), or the wall hit (+1/-1) and its offset s (``out`` is the state there, before the reset).
    """
    top = 0
    stack_k[0] = k0
    stack_s[0] = 0.0
    stack_z[0, :] = z
    za = np.empty(6)
    zb = np.empty(6)
    reached = 0.0
    out[:] = z
    while top >= 0:
        k = stack_k[top]
        s = stack_s[top]
        za[:] = stack_z[top]
        top -= 1
        _apply(table[k], za, zb)
        L = lengths[k]
        B = row_norm * growth[k] * _max_abs(za)
        up = _may_reach(za[2], za[3], zb[2], zb[3], L, B)
        down = _may_reach(-za[2], -za[3], -zb[2], -zb[3], L, B)
        if not (up or down) or (k == LEVELS and abs(zb[2]) < 1.0):
            out[:] = zb  # free, or a tangency within rounding
            reached = s + L
            continue
        if k == LEVELS:
            out[:] = zb
            return (1 if zb[2] >= 1.0 else -1), s + L
        top += 1  # right half, then left half on top of it
        stack_k[top] = k + 1
        stack_s[top] = s + lengths[k + 1]
        _apply(table[k + 1], za, stack_z[top])
        top += 1
        stack_k[top] = k + 1
        stack_s[top] = s
        stack_z[top, :] = za
    return 0, reached


@jit
def _run(table, lengths, growth, row_norm, kappa_c, kappa_q, y0, t0, t1, h, stick_speed, max_impacts, capacity):
    """Samples every h from t0 to t1 (t1 last) with the impacts among them; see :class:`ImpactFlow`.
    Stops with code _FULL when more than ``capacity`` impacts would be stored."""
    count = int(math.ceil((t1 - t0) / h - 1e-12))
    times = np.empty(count + 1 + capacity)
    states = np.empty((count + 1 + capacity, 4))
    impacts = np.empty((capacity, 4))  # t, side, w'-, w'+
    stack_z = np.empty((2 * LEVELS + 4, 6))
    stack_k = np.empty(2 * LEVELS + 4, dtype=np.int64)
    stack_s = np.empty(2 * LEVELS + 4)
    z = np.empty(6)
    zn = np.empty(6)
    z[:4] = y0
    times[0] = t0
    states[0] = y0
    rows, hits = 1, 0
    for j in range(count):
        ta = t0 + j * h
        tb = t1 if j == count - 1 else t0 + (j + 1) * h
        done = 0.0
        while True:
            tau = ta + done
            z[4] = math.cos(tau)
            z[5] = math.sin(tau)
            rest = (tb - tau) / h  # in steps; taken as its binary expansion
            side = 0
            for k in range(LEVELS + 1):
                unit = lengths[k] / h
                if rest < unit * (1.0 - 1e-9):
                    continue
                side, s = _piece(table, lengths, growth, row_norm, z, k, zn, stack_z, stack_k, stack_s)
                z[:] = zn
                if side != 0:
                    done += s
                    break
                rest -= unit
                done += s
            if side == 0:
                break
            if hits >= capacity:
                return times, states, impacts, rows, hits, _FULL
            v_minus = z[3]
            speed = abs(v_minus)
            if speed > 0.0:
                loss = kappa_c * speed**kappa_q
            else:  # the limit of (21) at zero speed
                loss = kappa_c if kappa_q == 0.0 else (0.0 if kappa_q > 0.0 else math.inf)
            impacts[hits, 0] = ta + done
            impacts[hits, 1] = side
            impacts[hits, 2] = v_minus
            if loss > 1.0:
                impacts[hits, 3] = math.nan
                return times, states, impacts, rows, hits + 1, _KAPPA_NOT_REAL
            z[2] = side  # exactly on the wall, so the next flight starts inside
            z[3] = -math.sqrt(1.0 - loss) * v_minus
            impacts[hits, 3] = z[3]
            hits += 1
            times[rows] = ta + done
            states[rows] = z[:4]
            rows += 1
            if abs(z[3]) < stick_speed:
                return times, states, impacts, rows, hits, _STICKING
            if hits >= max_impacts:
                return times, states, impacts, rows, hits, _MAX_IMPACTS
        times[rows] = tb
        states[rows] = z[:4]
        rows += 1
    return times, states, impacts, rows, hits, _FINISHED


class ImpactFlow:
    """The compiled exact flow of (8) for one parameter set, sampled every ``step``.

    ``run(y0, t0, t1, ...)`` returns the arrays of :class:`~slosh_bif.simulation.vibro_impact.ImpactTrajectory`.
    """

    def __init__(self, params: Params, step: float = 0.05):
        if not (np.isfinite(step) and 0 < step <= 0.5):
            raise ValueError(f"sample_step must be in (0, 0.5]; got {step!r}")
        model = ImpactModel(params)
        K = model.augmented()
        self.step = float(step)
        self.lengths = self.step * 0.5 ** np.arange(LEVELS + 2)
        self.table = np.array([linalg.expm(K * L) for L in self.lengths])
        self.growth = np.exp(np.abs(K).sum(axis=1).max() * self.lengths)
        self.row_norm = float(np.abs(K[3]).sum())  # |w''| <= row_norm |z|
        P = params
        self.kappa_c = float(dissipation_at_unit_speed(P.lam, P.chi, P.n, P.pbar))
        self.kappa_q = P.pbar / (P.n + 1)

    def run(self, y0, t0: float, t1: float, *, stick_speed: float, max_impacts: int):
        """``(t, y, impacts, code)``: sample times (with the impact instants), states ``(4, N)``
        (post-impact at an impact), impacts ``(K, 4)`` rows ``t, side, w'-, w'+`` and the end code
        (0 finished, 1 sticking, 2 kappa not real, 3 ``max_impacts`` reached)."""
        count = int(math.ceil((t1 - t0) / self.step - 1e-12))
        y0 = np.asarray(y0, dtype=float)
        capacity = min(max_impacts, 2 * count + 64)
        while True:  # rerun with room for more impacts: the same inputs give the same run
            times, states, impacts, rows, hits, code = _run(
                self.table, self.lengths, self.growth, self.row_norm, self.kappa_c, self.kappa_q,
                y0, float(t0), float(t1), self.step, float(stick_speed), max_impacts, capacity,
            )
            if code != _FULL:
                return times[:rows], states[:rows].T, impacts[:hits], int(code)
            capacity = min(max_impacts, 4 * capacity)
