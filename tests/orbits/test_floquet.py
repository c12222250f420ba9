"""Floquet multipliers by the periodic Schur decomposition (issue 19): against 60-digit mpmath
eigenvalues of the same product, across arc counts, against Liouville's formula, and where the
formed product measurably fails."""

import mpmath
import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.orbits import ShootingProblem, orbit_at
from slosh_bif.orbits.floquet import floquet_multipliers, periodic_schur

RNG = np.random.default_rng(19)


def _orthogonal(n=4):
    q, _ = np.linalg.qr(RNG.normal(size=(n, n)))
    return q


def _product_with_known_spread(multipliers, m, coupling=0.5, pair_angle=None):
    """m arc matrices Q_k T_k Q_{k-1}^T (Q_m = Q_0) whose product is similar to T_m ... T_1:
    upper triangular T_k with diagonal multipliers^(1/m) (a rotation block for a complex pair)."""
    Q = [_orthogonal() for _ in range(m)] + []
    Q.append(Q[0])
    mats = []
    for k in range(m):
        T = np.diag(np.abs(multipliers) ** (1.0 / m)) + coupling * np.triu(RNG.normal(size=(4, 4)), 1)
        if pair_angle is not None:  # rows 1, 2: r R(theta / m), a complex pair of modulus r^m
            r = abs(multipliers[1]) ** (1.0 / m)
            c, s = np.cos(pair_angle / m), np.sin(pair_angle / m)
            T[1:3, 1:3] = r * np.array([[c, -s], [s, c]])
        mats.append(Q[k + 1] @ T @ Q[k].T)
    return mats


def _mpmath_eigenvalues(mats):
    mpmath.mp.dps = 60
    P = mpmath.eye(4)
    for M in mats:
        P = mpmath.matrix(M.tolist()) * P
    mu = np.array([complex(e) for e in mpmath.eig(P, left=False, right=False)])
    return mu[np.argsort(-np.abs(mu))]


def _formed(mats):
    P = np.eye(4)
    for M in mats:
        P = M @ P
    mu = np.linalg.eigvals(P)
    return mu[np.argsort(-np.abs(mu))]


def _rel(a, b):
    return np.max(np.abs(a - b) / np.abs(b))


# "auto": the sweeps compiled (slosh_bif.flows.periodic_qr) where numba is; "numpy": numpy's QR
BACKENDS = ["auto", "numpy"]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("m", [4, 8])
@pytest.mark.parametrize("spread", [1e12, 1e14])
def test_a_spread_beyond_1e12_defeats_the_formed_product_not_the_periodic_schur(m, spread, backend):
    # The periodic Schur error is about eps times the spread of one arc, spread^(1/m): 1e-13 here
    # (with 2 arcs and a spread of 1e14 it is 2.5e-10); the formed product's is eps times the spread.
    mats = _product_with_known_spread(np.array([np.sqrt(spread), 3.0, 0.5, 1 / np.sqrt(spread)]), m)
    exact = _mpmath_eigenvalues(mats)
    schur = periodic_schur(mats, backend=backend)
    assert schur.converged
    assert _rel(schur.multipliers, exact) < 1e-10
    assert _rel(_formed(mats), exact) > 1e-7  # the smallest multiplier is lost in the formed product


@pytest.mark.parametrize("spread", [1e2, 1e14])
def test_floquet_multipliers_take_the_formed_product_only_where_it_is_accurate(spread):
    # A small spread: the formed product's eigenvalues (cheap) to 1e-12; a spread of 1e14: the
    # periodic Schur's, where the formed product's smallest multiplier is wrong (the test above).
    mats = _product_with_known_spread(np.array([np.sqrt(spread), 3.0, 0.5, 1 / np.sqrt(spread)]), 4)
    assert _rel(floquet_multipliers(mats), _mpmath_eigenvalues(mats)) < 1e-11


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("m", [2, 4])
def test_complex_pairs_stay_in_two_by_two_blocks(m, backend):
    mats = _product_with_known_spread(np.array([1e5, 0.8, 0.8, 1e-7]), m, pair_angle=2.0)
    exact = _mpmath_eigenvalues(mats)
    schur = periodic_schur(mats, backend=backend)
    assert (1, 3) in schur.blocks
    # the pair is matched as a set (conjugates can come in either order)
    np.testing.assert_allclose(
        np.sort_complex(schur.multipliers[1:3]), np.sort_complex(exact[1:3]), rtol=1e-10
    )
    assert _rel(schur.multipliers[[0, 3]], exact[[0, 3]]) < 1e-10


@pytest.mark.parametrize("n", [4, 8])
def test_the_compiled_householder_qr_is_numpys_with_a_positive_diagonal(n):
    from slosh_bif.flows.periodic_qr import householder_qr

    for scale in (1.0, 1e-8, 1e8):
        A = scale * RNG.normal(size=(n, n))
        Q, R = np.empty((n, n)), np.empty((n, n))
        householder_qr(A, Q, R)
        q, r = np.linalg.qr(A)
        signs = np.where(np.diag(r) < 0, -1.0, 1.0)
        np.testing.assert_allclose(Q, q * signs, atol=1e-13)
        np.testing.assert_allclose(R, signs[:, None] * r, atol=1e-13 * scale)
        assert np.all(np.diag(R) > 0) and np.all(np.tril(R, -1) == 0)
        np.testing.assert_allclose(Q.T @ Q, np.eye(n), atol=1e-14)


def test_non_finite_factors_give_nan_multipliers():
    mats = [np.eye(4), np.full((4, 4), np.nan)]
    assert np.all(np.isnan(periodic_schur(mats).multipliers))
    with pytest.raises(ValueError, match="square matrices"):
        periodic_schur([np.eye(4), np.eye(3)])
    with pytest.raises(ValueError, match="backend"):
        periodic_schur([np.eye(4), np.eye(4)], backend="lapack")


@pytest.fixture(scope="module")
def fig10_orbit_by_arcs():
    """The unstable resonant orbit of the Fig. 10 set (multipliers ~16 and ~0.03), converged with
    1, 2, 4 and 8 arcs at rtol 1e-12."""
    P = get_preset("fig10").params
    guess = np.array([-2.29697839, 0.4870925, 0.62950163, -1.6026986])
    out = {}
    for m in (1, 2, 4, 8):
        problem = ShootingProblem(P, segments=m, rtol=1e-12, atol=1e-14)
        orbit = orbit_at(problem, problem.initial_states(guess), P.sigma, tol=1e-11)
        assert orbit.converged
        guess = orbit.y0
        out[m] = (problem, problem.initial_states(orbit.y0), orbit)
    return P, out


def test_multipliers_agree_across_arc_counts_and_with_liouville(fig10_orbit_by_arcs):
    P, runs = fig10_orbit_by_arcs
    reference = runs[8][2].multipliers
    assert abs(reference[0]) > 10 and abs(reference[-1]) < 0.1  # the spread the issue names
    for m, (problem, x, orbit) in runs.items():
        np.testing.assert_allclose(orbit.multipliers, reference, rtol=1e-9, err_msg=f"{m} arcs")
        trace = problem.liouville_trace(x, P.sigma)
        assert abs(np.prod(orbit.multipliers).real - np.exp(trace)) <= 1e-10 * np.exp(trace)
