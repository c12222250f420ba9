"""Restitution law (19)-(21), (31), (39), (40) against quadrature, limits and a direct simulation."""

import numpy as np
import pytest
from scipy import integrate

from slosh_bif.model import manifold, restitution


@pytest.mark.parametrize(
    "n, pbar", [(1, 1), (6, 0), (6, -2), (6, 4), (10, 0), (50, 0), (50, -2), (50, 2), (3, -3)]
)
def test_closed_form_I_matches_quadrature_of_eq18(n, pbar):
    p = (pbar + n) / 2
    value, err = integrate.quad(
        lambda z: z ** (2 * p) * np.sqrt(1 - z ** (2 * (n + 1))), 0, 1, epsabs=1e-14, epsrel=1e-13, limit=200
    )
    assert restitution.I(n, pbar) == pytest.approx(value, rel=1e-10)


def test_I_at_pbar_zero_is_eq20():
    n = np.arange(1, 60)
    np.testing.assert_allclose(restitution.I(n, 0), np.pi / (4 * (n + 1)), rtol=1e-13)


def test_I_rejects_divergent_pbar():
    with pytest.raises(ValueError, match=r"pbar > -\(n\+1\)"):
        restitution.I(6, -7)


@pytest.mark.parametrize("n", [1, 6, 10, 50])
def test_kappa_at_pbar_zero_is_the_newtonian_limit_and_speed_independent(n):
    v0 = np.logspace(-2, 2, 9)
    k = restitution.kappa(v0, lam=0.25, chi=1.0, n=n, pbar=0)
    np.testing.assert_allclose(k, restitution.kappa_newtonian(0.25, 1.0, n), rtol=1e-14)


def test_kappa_speed_dependence_has_the_sign_of_pbar():
    v0 = np.array([0.5, 1.0, 2.0])
    assert np.all(np.diff(restitution.kappa(v0, 0.25, 1.0, 6, 2)) < 0)  # pbar > 0: faster impacts lose more
    assert np.all(np.diff(restitution.kappa(v0, 0.25, 1.0, 6, -2)) > 0)


def test_kappa_reports_where_it_is_not_real():
    with pytest.raises(ValueError, match=r"kappa \(eq. 21\) is not real for impact speed v0 in \[1, 10\]"):
        restitution.kappa([0.01, 1.0, 10.0], lam=0.35, chi=0.2, n=6, pbar=2)
    with pytest.raises(ValueError, match="impact speed v0 must be positive and finite"):
        restitution.kappa([1.0, np.nan], 0.35, 0.2, 50, 0)


def test_rho_is_eq31_and_its_limits():
    assert restitution.rho(1.0) == 0.0
    assert restitution.rho(0.5) == pytest.approx(2 * 0.5 / (np.pi * 1.5), rel=1e-15)
    with pytest.raises(ValueError, match=r"kappa must be in \(0, 1\]"):
        restitution.rho(1.2)


@pytest.mark.parametrize("n, pbar", [(6, -2), (10, 2), (50, 2), (50, -2)])
def test_kappa_on_manifold_solves_eq39(n, pbar):
    lam, chi = 0.25, 1.0
    A = np.array([0.4, 0.7, 1.0, 2.0, 5.0])
    sol = restitution.kappa_on_manifold(A, lam, chi, n, pbar)
    assert np.all(sol.exists)
    # Independent evaluation: the impact speed (38) from alpha(A, rho(kappa)) fed to eq. (21).
    alpha = manifold.alpha(A, restitution.rho(sol.kappa))
    speed = alpha * (2 / np.pi + restitution.rho(sol.kappa))
    np.testing.assert_allclose(sol.kappa, restitution.kappa(speed, lam, chi, n, pbar), rtol=1e-12, atol=0)
    np.testing.assert_allclose(sol.alpha, alpha, rtol=1e-14)


def test_kappa_on_manifold_is_newtonian_at_pbar_zero():
    sol = restitution.kappa_on_manifold([0.5, 1.0, 3.0], 0.25, 1.0, 10, 0)
    np.testing.assert_allclose(sol.kappa, restitution.kappa_newtonian(0.25, 1.0, 10), rtol=1e-12)


def test_kappa_on_manifold_reports_amplitudes_below_the_manifold_end():
    k = restitution.kappa_newtonian(0.35, 0.2, 6)
    A_end = manifold.a_min(restitution.rho(k))
    A = np.array([0.5 * A_end, 2 * A_end])
    with pytest.raises(ValueError, match="no restitution coefficient in .* solves eq. \\(39\\)"):
        restitution.kappa_on_manifold(A, 0.35, 0.2, 6, 0)
    sol = restitution.kappa_on_manifold(A, 0.35, 0.2, 6, 0, strict=False)
    assert list(sol.exists) == [False, True] and np.isnan(sol.kappa[0])


# --- the physical check of eq. (21): one particle in the wall of eq. (10) ---------------------


def _delta(lam, chi, n, pbar, v0=1.0):
    return 1 - restitution.kappa(v0, lam, chi, n, pbar) ** 2


@pytest.mark.parametrize("n, pbar", [(6, 0), (10, 0), (50, 0), (6, -2), (6, 2), (50, 2)])
def test_eq21_error_is_second_order_in_the_dissipation(n, pbar):
    """kappa_sim - kappa_21 = C delta**2 (1 + O(delta)): halving lam quarters the error."""
    chi, v0 = 0.2, 1.0
    errors = [
        restitution.simulate_rebound(v0, lam, chi, n, pbar) - restitution.kappa(v0, lam, chi, n, pbar)
        for lam in (0.04, 0.02)
    ]
    assert errors[0] > 0 and errors[1] > 0  # eq. (21) always underestimates kappa
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.06)


@pytest.mark.parametrize("n", [6, 10, 50])
def test_newtonian_eq21_error_is_pi2_lam2_over_4_chi_n_plus_1(n):
    """At pbar = 0 the leading error is delta**2/4 = pi**2 lam**2 / (4 chi (n+1)): O(lam**2 / n)."""
    lam, chi = 0.02, 0.2
    error = restitution.simulate_rebound(1.0, lam, chi, n, 0) - restitution.kappa_newtonian(lam, chi, n)
    assert error == pytest.approx(np.pi**2 * lam**2 / (4 * chi * (n + 1)), rel=0.05)


@pytest.mark.parametrize("n, pbar", [(6, -2), (6, 2), (6, 4), (50, -2), (50, 2)])
@pytest.mark.parametrize("v0", [0.3, 1.0, 3.0])
def test_eq21_error_constant_is_q_over_8(n, pbar, v0):
    """kappa_sim - kappa_21 -> (q/8) delta(v0)**2, q = 2 + pbar/(n+1) the speed exponent of (18).

    Measured, then confirmed over n, pbar and v0; at delta ~ 0.03 the O(delta**3) rest is < 2 %.
    """
    chi = 0.2
    lam = 0.03 / (
        restitution.dissipation_at_unit_speed(1.0, chi, n, pbar) * v0 ** (pbar / (n + 1))
    )  # delta = 0.03
    delta = _delta(lam, chi, n, pbar, v0)
    error = restitution.simulate_rebound(v0, lam, chi, n, pbar) - restitution.kappa(v0, lam, chi, n, pbar)
    assert error / delta**2 == pytest.approx((2 + pbar / (n + 1)) / 8, rel=0.02)


def test_simulate_rebound_reports_an_overdamped_wall():
    with pytest.raises(RuntimeError, match="did not return to x = 0"):
        restitution.simulate_rebound(1.0, lam=50.0, chi=0.2, n=1, pbar=-1)


def test_the_speed_laws_share_one_interface_and_agree_where_eq21_is_exact():
    """speed_law: eq. (21) (D = 1) and the measured wall answer kappa(v0), D(v0) and their slopes;
    the slopes of (21) match central differences, and at small dissipation the measured wall's
    kappa approaches (21)'s (the error is second order in delta)."""
    from slosh_bif.model import Params
    from slosh_bif.model.restitution import SpeedLaw, speed_law

    P = Params(eps=0.05, beta=0.3, gamma=0.5, sigma=0.0, Abar=0.5, lam=0.005, chi=1.0, n=6, pbar=2)
    first, wall = speed_law(P), speed_law(P, "corrected")
    assert isinstance(first, SpeedLaw) and isinstance(wall, SpeedLaw)
    v, h = np.array([0.3, 1.0, 4.0]), 1e-6
    k, dk, d, dd = first.slopes(v)
    np.testing.assert_allclose(dk, (first.kappa(v + h) - first.kappa(v - h)) / (2 * h), rtol=1e-6)
    assert np.all(d == 1.0) and np.all(dd == 0.0)
    delta = 1.0 - k**2
    assert np.all(np.abs(wall.kappa(v) - k) < delta**2)
    assert np.all(wall.clearance(v) > 1.0)  # the particle penetrates the wall
    with pytest.raises(TypeError, match="Params"):
        speed_law({"lam": 0.1})
