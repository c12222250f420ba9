"""The compiled DOP853 loop: the explicit Runge-Kutta pair of Hairer, Norsett and Wanner with exactly
the error norm, step-size control and initial-step rule of scipy's ``solve_ivp(method="DOP853")``
(its coefficients written from scipy's by the derivation, ``_generated/dop853_tableau.py``, so
that the loop does not import scipy.integrate), compiled by numba around the scalar
kernels that the sympy derivation writes for (9) (``_generated/kernels.py``): (9) alone, (9) with
everything shooting needs (variational equations, two parameter sensitivities, the Liouville
integral; the (sigma, Abar) kernel or the pair kernel for any two parameters), (9) with its
variational equations of first to third order along any directions
(:mod:`slosh_bif.flows.smooth.variations`), and (9) with the random forcing of (47), the noise
spline of :mod:`slosh_bif.flows.noise` added where cos(tau) enters.
:mod:`slosh_bif.flows.smooth.integrator` is the interface. numba compiles these loops just in time
(with its on-disk cache), loaded on first use by :mod:`slosh_bif.flows.loops`; without numba these
are the plain Python functions (never called: the scipy path runs instead).
"""

from __future__ import annotations

import math
import sys

import numpy as np

from slosh_bif.flows.compiled import HAVE_NUMBA, forget_stale_compilations, numba
from slosh_bif.flows.compiled import jit as _jit
from slosh_bif.flows.smooth import variations as _variations
from slosh_bif.flows.smooth.dop853_interface import ALONG_SIZE, SHOOTING_SIZE, WHICH
from slosh_bif.model import powers as _powers
from slosh_bif.model._generated import kernels as _kernels

__all__ = ["HAVE_NUMBA", "KERNELS", "dop853_loop", "grid_loop", "arcs_loop"]

if HAVE_NUMBA:  # before any kernel compiles: the kernels' int_power becomes repeated squaring here

    @numba.extending.overload(_powers.int_power)
    def _int_power_compiled(x, k):
        return _powers.int_power_by_squaring


@_jit
def _rms(v, scale, count):
    total = 0.0
    for i in range(count):
        r = v[i] / scale[i]
        total += r * r
    return math.sqrt(total / count)


_ALONG, _ALONG_EXTRA, _ALONG_SIGMA_ABAR = WHICH["along"], WHICH["along_extra"], WHICH["along_sigma_abar"]


@_jit(inline=True)
def _controlled(which, n):
    """The components in the error norm: all, except for the along kernel, whose derivatives along a
    direction ride on the steps its first 29 (the shooting system's) choose, so that these are the
    very numbers of the pair kernel's integration whatever the direction."""
    return SHOOTING_SIZE if which == _ALONG else n


@_jit
def _grid_loop(which, taus, z0, pars, rtol, atol, max_steps, A, B, C, E3, E5):
    """States at every time of ``taus``, the step size carried from one interval to the next."""
    out = np.empty((taus.shape[0], z0.shape[0]))
    out[0] = z0
    h = 0.0
    for k in range(1, taus.shape[0]):
        z, steps, rejected, nfev, h, status = _dop853_loop(
            which,
            taus[k - 1],
            taus[k],
            out[k - 1],
            pars,
            rtol,
            atol,
            h,
            max_steps,
            np.empty((0, 0)),
            A,
            B,
            C,
            E3,
            E5,
        )
        if status != 0:
            return out, k, status
        out[k] = z
    return out, taus.shape[0], 0


_NOISE_AT = 9  # pars[9:] holds the noise spline table (noise.BandLimitedNoise.table) for "noisy"


def _noise_force(tau, pars):
    """F_w(tau) from the spline table in ``pars[9:]`` (the scalar twin of BandLimitedNoise.__call__)."""
    t0 = pars[_NOISE_AT]
    dt = pars[_NOISE_AT + 1]
    m = int(pars[_NOISE_AT + 2])
    degree = int(pars[_NOISE_AT + 3])
    i = int((tau - t0) / dt)
    i = min(max(i, 0), m - 1)
    s = tau - (t0 + i * dt)
    k = _NOISE_AT + 4 + (degree + 1) * i
    value = pars[k]
    for j in range(1, degree + 1):
        value = value * s + pars[k + j]
    return value


def _noisy_kernel_py(tau, y, out, pars):
    """(9) with the forcing eps*(Abar cos tau + F_w(tau)) of (47): F_w enters where cos tau does."""
    _plain_kernel(tau, y, out, pars)
    force = pars[0] * _noise_force(tau, pars)
    out[1] += force
    out[3] += force


_RAW = {
    "plain": _kernels.smooth_rhs_kernel,
    "shooting": _kernels.smooth_shooting_kernel,
    "pair": _kernels.smooth_pair_kernel,
    "variations": _variations.variations_kernel,
    "along": _kernels.smooth_along_kernel,
    "along_extra": _kernels.smooth_along_extra_kernel,
    "along_sigma_abar": _kernels.smooth_along_sigma_abar_kernel,
}
_plain_kernel = _jit(_RAW["plain"], inline=True)
_shooting_kernel = _jit(_RAW["shooting"], inline=True)
_pair_kernel = _jit(_RAW["pair"], inline=True)
_variations_kernel = _jit(_RAW["variations"], inline=True)
_along_kernel = _jit(_RAW["along"], inline=True)
_along_extra_kernel = _jit(_RAW["along_extra"], inline=True)
_along_sigma_abar_kernel = _jit(_RAW["along_sigma_abar"], inline=True)
_noise_force = _jit(_noise_force)
_RAW["noisy"] = _noisy_kernel_py
_noisy_kernel = _jit(_noisy_kernel_py, inline=True)


def _switch(which, tau, z, out, pars):
    # One entry point with a switch rather than the kernel as an argument: numba cannot cache a
    # function that takes another compiled function as argument, and recompiling costs ~1 s a process.
    if which == 0:
        _plain_kernel(tau, z, out, pars)
    elif which == 1:
        _shooting_kernel(tau, z, out, pars)
    elif which == 3:
        _pair_kernel(tau, z, out, pars)
    elif which == 4:
        _variations_kernel(tau, z, out, pars)
    elif which == _ALONG:
        _along_kernel(tau, z, out, pars)
    elif which == _ALONG_EXTRA:
        _along_extra_kernel(tau, z, out, pars)
    elif which == _ALONG_SIGMA_ABAR:
        _along_sigma_abar_kernel(tau, z, out, pars)
    else:
        _noisy_kernel(tau, z, out, pars)


# Inlined where it runs every stage (a call costs as much as a small right-hand side), called where
# it runs once an integration: each inlined copy holds every kernel, and numba compiles each copy
_kernel = _jit(_switch, inline=True)
_kernel_call = _jit(_switch)


@_jit
def _dop853_loop(which, t0, t1, z0, pars, rtol, atol, h, max_steps, tape, A, B, C, E3, E5):
    """The hot loop from t0 to t1: (end state, steps, rejected, nfev, next step, status).

    ``tape`` (rows, 2 + 13 n): accepted step k is written to row k while there are rows, as
    [tau, h, the states its 13 stages were evaluated at], what :mod:`slosh_bif.flows.smooth.tape`
    replays equations along (an empty one: nothing kept; a rejected trial's are overwritten)."""
    n = z0.shape[0]
    nc = _controlled(which, n)
    K = np.empty((13, n))
    z = z0.copy()
    znew = np.empty(n)
    tmp = np.empty(n)
    scale = np.empty(n)
    _kernel_call(which, t0, z, K[0], pars)
    nfev = 1
    span = t1 - t0
    if h <= 0.0:  # scipy's initial step (Hairer, Norsett & Wanner II.4) for an order-7 estimate
        for i in range(n):
            scale[i] = atol + abs(z[i]) * rtol
        d0 = _rms(z, scale, nc)
        d1 = _rms(K[0], scale, nc)
        h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h0 = min(h0, span)
        for i in range(n):
            tmp[i] = z[i] + h0 * K[0, i]
        _kernel_call(which, t0 + h0, tmp, K[1], pars)
        nfev += 1
        for i in range(n):
            znew[i] = K[1, i] - K[0, i]
        d2 = _rms(znew, scale, nc) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h = min(100 * h0, h1, span)
    t = t0
    steps = 0
    rejected = 0
    status = 0
    while t < t1:
        if steps >= max_steps:
            status = 1
            break
        step_rejected = False
        while True:
            min_step = 10 * abs(np.nextafter(t, np.inf) - t)
            if not h >= min_step:  # NaN as well: a step size from a right-hand side that is not finite
                status = 2 if h == h else 3
                break
            t_new = t + h
            if t_new > t1:
                t_new = t1
            hh = t_new - t
            keep = steps < tape.shape[0]
            if keep:
                tape[steps, 0] = t
                tape[steps, 1] = hh
                for i in range(n):
                    tape[steps, 2 + i] = z[i]
            for s in range(1, 13):  # the 13th stage at the new state (the next step's first)
                if s == 12:
                    for i in range(n):
                        acc = 0.0
                        for j in range(12):
                            acc += B[j] * K[j, i]
                        znew[i] = z[i] + hh * acc
                    ts, state = t_new, znew
                else:
                    # the shooting system: row by row of K, contiguous and vectorised, zeros skipped
                    # (40 % faster at 29 components; 20 % slower at 4)
                    if n > 4:
                        for i in range(n):
                            tmp[i] = 0.0
                        for j in range(s):
                            a = A[s, j]
                            if a != 0.0:
                                for i in range(n):
                                    tmp[i] += a * K[j, i]
                        for i in range(n):
                            tmp[i] = z[i] + hh * tmp[i]
                    else:
                        for i in range(n):
                            acc = 0.0
                            for j in range(s):
                                acc += A[s, j] * K[j, i]
                            tmp[i] = z[i] + hh * acc
                    ts, state = t + C[s] * hh, tmp
                if keep:
                    for i in range(n):
                        tape[steps, 2 + n * s + i] = state[i]
                _kernel(which, ts, state, K[s], pars)  # its one inlined call
            nfev += 12
            err5 = 0.0
            err3 = 0.0
            for i in range(nc):
                sc = atol + max(abs(z[i]), abs(znew[i])) * rtol
                e5 = 0.0
                e3 = 0.0
                for j in range(13):
                    e5 += E5[j] * K[j, i]
                    e3 += E3[j] * K[j, i]
                e5 /= sc
                e3 /= sc
                err5 += e5 * e5
                err3 += e3 * e3
            if err5 == 0.0 and err3 == 0.0:
                error = 0.0
            else:
                error = abs(hh) * err5 / math.sqrt((err5 + 0.01 * err3) * nc)
            if error < 1.0:  # NaN compares false: a non-finite trial step is rejected
                factor = 10.0 if error == 0.0 else min(10.0, 0.9 * error ** (-1.0 / 8.0))
                if step_rejected:
                    factor = min(1.0, factor)
                h = hh * factor
                break
            h = hh * max(0.2, 0.9 * error ** (-1.0 / 8.0)) if error == error else hh * 0.2
            step_rejected = True
            rejected += 1
        if status != 0:
            break
        t = t_new
        for i in range(n):
            z[i] = znew[i]
            K[0, i] = K[12, i]
        steps += 1
        if not np.isfinite(z[0]):
            status = 3
            break
    return z, steps, rejected, nfev, h, status


@_jit
def _arcs_loop(which, taus, starts, directions, pars, rtol, atol, max_steps, tapes, A, B, C, E3, E5):
    """Every arc of multiple shooting in one call: arc k runs the shooting system from
    [starts[k], I, 0, 0] over [taus[k], taus[k + 1]] (the along kernel from [starts[k], I, 0, 0, 0,
    directions[k], 0, 0, 0]; ``directions`` is read by it alone), its first ``tapes.shape[1]``
    accepted steps written to ``tapes[k]`` (the caller's buffer; none kept where it has no rows).
    Returns (end states (m, 29 or 57), arcs done, status of the first that failed or 0, steps per
    arc); an arc of more steps than the buffer holds is integrated to its end all the same, its
    tape then incomplete. One call instead of one per arc: the Python around each call cost as
    much as a short arc at n = 6."""
    m = starts.shape[0]
    size = ALONG_SIZE if which == _ALONG else SHOOTING_SIZE
    out = np.full((m, size), np.nan)
    counts = np.zeros(m, dtype=np.int64)
    z0 = np.zeros(size)
    for k in range(m):
        for i in range(size):
            z0[i] = 0.0
        for i in range(4):
            z0[i] = starts[k, i]
            z0[4 + 5 * i] = 1.0
            if which == _ALONG:
                z0[SHOOTING_SIZE + i] = directions[k, i]
        z, steps, rejected, nfev, h, status = _dop853_loop(
            which, taus[k], taus[k + 1], z0, pars, rtol, atol, 0.0, max_steps, tapes[k], A, B, C, E3, E5
        )
        counts[k] = steps
        if status != 0:
            return out, k, status, counts
        for i in range(size):
            out[k, i] = z[i]
    return out, m, 0, counts


if HAVE_NUMBA:  # the loops and the tape's replay inline the kernels, the integer power and the variations
    sources = (_kernels, _powers, _variations, sys.modules[__name__])
    forget_stale_compilations(_dop853_loop, sources, ("dop853", "tape"), "dop853.kernels")

# The interface of :mod:`slosh_bif.flows.smooth.integrator` (its constants, the tableau that every loop
# takes last and the status codes, are in :mod:`slosh_bif.flows.smooth.dop853_interface`).
KERNELS = _RAW
dop853_loop, grid_loop, arcs_loop = _dop853_loop, _grid_loop, _arcs_loop
