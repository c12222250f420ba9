"""Floquet multipliers of a periodic orbit from the arc matrices of multiple shooting, by a periodic
Schur decomposition (periodic QR), without forming the monodromy matrix.

The monodromy matrix of (9) over a period is the product M = Phi_m ... Phi_1 of the arcs' state
transition matrices. Its eigenvalues, the Floquet multipliers, can span many decades (15.96 and
0.032 at the Fig. 10 orbit; far more at larger n and damping), and an eigensolver applied to the
formed product perturbs every eigenvalue by about eps |M|: a multiplier below eps |M| is lost. The
periodic Schur decomposition keeps the factors apart,

    Phi_k Q_{k-1} = Q_k R_k  (k = 1..m),   Q_m = Q_0 U,

with Q_k orthogonal, R_k upper triangular and U block diagonal: M = Q_0 (U R_m ... R_1) Q_0^T, so
the multipliers are the eigenvalues of the diagonal blocks U_bb (R_m)_bb ... (R_1)_bb (1 x 1 for
a real multiplier, 2 x 2 for a complex pair). Each factor is computed to eps |Phi_k|, and the
diagonal products carry relative errors of about eps times the spread of one arc, not of the
whole period: with m arcs a spread of 10^12 costs 10^3 eps instead of 10^12 eps.

The Q_k are found by periodic orthogonal iteration (the QR sweep above, repeated) started from
the Schur vectors of the formed product ordered by decreasing modulus: those span the dominant
invariant subspaces accurately even where the small eigenvalues of the formed product are wrong,
so a few sweeps settle the decomposition; the sweep stops when U is block diagonal to rounding.
The sweeps run compiled (:mod:`slosh_bif.flows.periodic_qr`) where numba is, in numpy otherwise.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.flows.loops import compiled

__all__ = ["PeriodicSchur", "periodic_schur", "floquet_multipliers"]


@dataclasses.dataclass(frozen=True)
class PeriodicSchur:
    """``multipliers`` (largest modulus first); the factors ``Q`` (m + 1 orthogonal matrices,
    Q[m] = Q[0] U) and ``R`` (m upper triangular); ``blocks`` (index ranges of U's diagonal
    blocks); ``sweeps`` done and whether U became block diagonal (``converged``)."""

    multipliers: np.ndarray
    Q: list
    R: list
    U: np.ndarray
    blocks: list
    sweeps: int
    converged: bool


def _start_basis(mats) -> np.ndarray:
    """Orthonormal columns spanning the nested dominant invariant subspaces of the formed
    product, from its eigenvectors ordered by decreasing modulus (real and imaginary parts of a
    complex pair side by side); the identity when they are degenerate."""
    product = np.eye(mats[0].shape[0])
    for Phi in mats:
        product = Phi @ product
    mu, V = np.linalg.eig(product)
    columns, seen = [], set()
    for i in np.argsort(-np.abs(mu), kind="stable"):
        if i in seen:
            continue
        if abs(mu[i].imag) > 0:
            j = int(np.argmin(np.abs(mu - np.conj(mu[i])) + np.where(np.arange(len(mu)) == i, np.inf, 0)))
            seen.update((i, j))
            columns += [V[:, i].real, V[:, i].imag]
        else:
            seen.add(i)
            columns.append(V[:, i].real)
    basis = np.column_stack(columns)
    if not np.all(np.isfinite(basis)):
        return np.eye(product.shape[0])
    Q, R = np.linalg.qr(basis)
    return Q if np.min(np.abs(np.diag(R))) > 1e-8 * np.max(np.abs(np.diag(R))) else np.eye(product.shape[0])


def _sweep(mats, Q0):
    Q, Rs = [Q0], []
    for Phi in mats:
        q, r = np.linalg.qr(Phi @ Q[-1])
        signs = np.where(np.diag(r) < 0, -1.0, 1.0)  # a positive diagonal: the factorization is unique
        Q.append(q * signs)
        Rs.append(signs[:, None] * r)
    return Q, Rs


def _blocks(U, tol):
    """Index ranges [a, b) of the diagonal blocks of U: i and j (i > j) share a block when
    |U[i, j]| > tol, and a block is contiguous."""
    n = len(U)
    end = list(range(1, n + 1))
    for i in range(n):
        for j in range(i):
            if abs(U[i, j]) > tol:
                for k in range(j, i):
                    end[k] = max(end[k], i + 1)
    blocks, a = [], 0
    while a < n:
        b = end[a]
        k = a
        while k < b:  # a block ends where no row inside it reaches further
            b = max(b, end[k])
            k += 1
        blocks.append((a, b))
        a = b
    return blocks


def periodic_schur(mats, *, max_sweeps: int = 50, tol: float = 1e-14, backend: str = "auto") -> PeriodicSchur:
    """The periodic Schur decomposition of the product of the square matrices ``mats`` (the last
    factor leftmost; see the module docstring) and its eigenvalues, largest modulus first.
    ``backend``: "auto" sweeps in compiled code where numba is, "numpy" in numpy (the reference)."""
    if backend not in ("auto", "numpy"):
        raise ValueError(f"backend must be 'auto' or 'numpy'; got {backend!r}")
    try:
        stacked = np.array([np.asarray(Phi, dtype=float) for Phi in mats], dtype=float)
    except ValueError:  # matrices of different shapes
        stacked = np.empty(0)
    if stacked.ndim != 3 or stacked.shape[1] != stacked.shape[2] or not len(stacked):
        raise ValueError("mats must be a non-empty sequence of square matrices of one size")
    mats = list(stacked)
    n = stacked.shape[1]
    if not np.isfinite(stacked).all():
        return PeriodicSchur(np.full(n, np.nan + 0j), [], [], np.full((n, n), np.nan), [(0, n)], 0, False)
    if len(mats) == 1:  # one factor: its Schur form is all there is
        mu = np.linalg.eigvals(mats[0])
        return PeriodicSchur(mu[np.argsort(-np.abs(mu), kind="stable")], [], [], np.eye(n), [(0, n)], 0, True)
    Q0 = _start_basis(mats)
    loops = compiled() if backend == "auto" else None
    if loops is not None:  # the same sweeps, compiled (numpy's overhead on 4 x 4 QRs dominated them)
        Q, R, U, sweep, converged = loops.periodic_qr(stacked, np.ascontiguousarray(Q0), max_sweeps, tol)
        return _finish(list(Q), list(R), U, sweep, converged)
    converged, previous = False, None
    for sweep in range(1, max_sweeps + 1):
        Q, R = _sweep(mats, Q0)
        U = Q0.T @ Q[-1]
        # Converged when the coupling between blocks has stopped shrinking at rounding level;
        # the blocks themselves (complex pairs, equal moduli) never decouple.
        blocks = _blocks(U, 1e-6)
        outside = max(
            (
                abs(U[i, j])
                for i in range(n)
                for j in range(i)
                if not any(a <= j and i < b for a, b in blocks)
            ),
            default=0.0,
        )
        if outside <= tol * n or (previous is not None and outside >= previous and outside < 1e-10):
            converged = True
            break
        previous = outside
        Q0 = Q[-1]
    return _finish(Q, R, U, sweep, converged)


def _finish(Q, R, U, sweep, converged) -> PeriodicSchur:
    """The multipliers from U's diagonal blocks times the R_k's."""
    blocks = _blocks(U, 1e-10)
    diagonal = np.diagonal(np.asarray(R), axis1=1, axis2=2).T.tolist()  # R_k's diagonals, by row
    mu = []
    for a, b in blocks:
        if b - a == 1:  # a real multiplier: U_aa times the R_k's entries, as the block loop multiplies
            t = 1.0
            for r in diagonal[a]:
                t = r * t
            mu.append(U[a, a] * t)
            continue
        T = np.eye(b - a)
        for r in R:
            T = r[a:b, a:b] @ T
        mu.extend(np.linalg.eigvals(U[a:b, a:b] @ T))
    mu = np.asarray(mu, dtype=complex)
    return PeriodicSchur(mu[np.argsort(-np.abs(mu), kind="stable")], Q, R, U, blocks, sweep, converged)


def floquet_multipliers(mats, *, spread: float = 1e4) -> np.ndarray:
    """The eigenvalues of the product of ``mats`` (the last factor leftmost), largest modulus first.

    The formed product's eigenvalues when every one of them is at least |M| / ``spread`` (each
    is then perturbed by about eps |M| <= eps ``spread`` |mu|: 2e-12 relative at the default,
    times its condition number), else :func:`periodic_schur`'s. The periodic sweeps cost 40 times
    the product's eigensolver, and most orbits here need no more than the product.
    """
    if len(mats) > 1 and all(np.all(np.isfinite(Phi)) for Phi in mats):
        M = mats[0]
        for Phi in mats[1:]:
            M = Phi @ M
        mu = np.linalg.eigvals(M)
        if np.min(np.abs(mu)) * spread >= np.linalg.norm(M):
            return mu[np.argsort(-np.abs(mu), kind="stable")]
    return periodic_schur(mats).multipliers
