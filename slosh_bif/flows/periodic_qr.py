"""The periodic QR iteration of the Floquet multipliers' periodic Schur decomposition, compiled.

:mod:`slosh_bif.orbits.floquet` finds the orthogonal Q_k with Phi_k Q_{k-1} = Q_k R_k (k = 1..m) by
sweeps of QR factorizations of the arcs' 4 x 4 (or 8 x 8) transition matrices until U = Q_0^T Q_m
is block diagonal. numpy spends about 15 us of call overhead on each such factorization, and a
branch of period-2 or period-4 orbits at n = 50 asks for hundreds of thousands of them: here they
are Householder reflections in a numba loop (about 0.2 us each), with R's diagonal made positive,
the normalisation under which the factorization is unique, so the result is numpy's to rounding.
Loaded on first use with the integrator's loops (:mod:`slosh_bif.flows.loops`).
"""

from __future__ import annotations

import math

import numpy as np

from slosh_bif.flows.compiled import jit

__all__ = ["periodic_qr", "householder_qr"]


@jit
def householder_qr(A, Q, R):
    """A = Q R (A square) written into Q (orthogonal) and R (upper triangular, diagonal >= 0)."""
    n = A.shape[0]
    v = np.empty(n)
    for i in range(n):
        for j in range(n):
            R[i, j] = A[i, j]
            Q[i, j] = 1.0 if i == j else 0.0
    for k in range(n - 1):
        norm = 0.0
        for i in range(k, n):
            norm += R[i, k] * R[i, k]
        norm = math.sqrt(norm)
        if norm == 0.0:
            continue
        alpha = -norm if R[k, k] >= 0.0 else norm  # the reflection sends the column to alpha e_k
        for i in range(k, n):
            v[i] = R[i, k]
        v[k] -= alpha
        vv = 0.0
        for i in range(k, n):
            vv += v[i] * v[i]
        if vv == 0.0:
            continue
        for j in range(k, n):  # R <- (I - 2 v v^T / v^T v) R
            s = 0.0
            for i in range(k, n):
                s += v[i] * R[i, j]
            f = 2.0 * s / vv
            for i in range(k, n):
                R[i, j] -= f * v[i]
        for i in range(n):  # Q <- Q (I - 2 v v^T / v^T v)
            s = 0.0
            for j in range(k, n):
                s += Q[i, j] * v[j]
            f = 2.0 * s / vv
            for j in range(k, n):
                Q[i, j] -= f * v[j]
        for i in range(k + 1, n):
            R[i, k] = 0.0
    for i in range(n):
        if R[i, i] < 0.0:
            for j in range(n):
                R[i, j] = -R[i, j]
                Q[j, i] = -Q[j, i]


@jit
def _outside_blocks(U, tol):
    """The largest |U[i, j]| (i > j) between different diagonal blocks of U, the blocks joined
    where |U[i, j]| > tol (``floquet._blocks``'s rule: contiguous index ranges)."""
    n = U.shape[0]
    end = np.arange(1, n + 1)
    for i in range(n):
        for j in range(i):
            if abs(U[i, j]) > tol:
                for k in range(j, i):
                    end[k] = max(end[k], i + 1)
    block = np.empty(n, dtype=np.int64)
    a, label = 0, 0
    while a < n:
        b = end[a]
        k = a
        while k < b:
            b = max(b, end[k])
            k += 1
        for k in range(a, b):
            block[k] = label
        label += 1
        a = b
    outside = 0.0
    for i in range(n):
        for j in range(i):
            if block[i] != block[j]:
                outside = max(outside, abs(U[i, j]))
    return outside


@jit
def periodic_qr(mats, Q0, max_sweeps, tol):
    """Sweeps of Phi_k Q_{k-1} = Q_k R_k from Q_0 = ``Q0`` (``mats``: (m, n, n)), each starting
    from the last one's Q_m, until U = Q_0^T Q_m is block diagonal to rounding (the coupling
    between blocks at most tol n, or no longer shrinking below 1e-10). Returns (Q (m + 1, n, n),
    R (m, n, n), U, sweeps done, converged)."""
    m, n = mats.shape[0], mats.shape[1]
    Q = np.empty((m + 1, n, n))
    R = np.empty((m, n, n))
    P = np.empty((n, n))
    U = np.empty((n, n))
    Q[0] = Q0
    previous = -1.0
    sweeps = 0
    converged = False
    for sweep in range(1, max_sweeps + 1):
        sweeps = sweep
        for k in range(m):
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for t in range(n):
                        s += mats[k, i, t] * Q[k, t, j]
                    P[i, j] = s
            householder_qr(P, Q[k + 1], R[k])
        for i in range(n):
            for j in range(n):
                s = 0.0
                for t in range(n):
                    s += Q[0, t, i] * Q[m, t, j]
                U[i, j] = s
        outside = _outside_blocks(U, 1e-6)
        if outside <= tol * n or (previous >= 0.0 and outside >= previous and outside < 1e-10):
            converged = True
            break
        previous = outside
        if sweep < max_sweeps:
            Q[0] = Q[m]
    return Q, R, U, sweeps, converged
