"""Shooting: closed-form periodic response of a linear oscillator, monodromy, Liouville, failures."""

import numpy as np
import pytest
from scipy import linalg

from slosh_bif import SmoothModel, get_preset
from slosh_bif.shooting import period_map, periodic_orbit, shoot

ZETA, OMEGA = 0.05, 1.3
A_LIN = np.array([[0.0, 1.0], [-(OMEGA**2), -2 * ZETA]])


def lin_rhs(tau, y):
    return A_LIN @ y + np.array([0.0, np.cos(tau)])


def lin_jac(tau, y):
    return A_LIN


def test_linear_forced_oscillator_periodic_response_and_monodromy():
    orbit = shoot(lin_rhs, lin_jac, [0.0, 0.0], 2 * np.pi, tol=1e-12, rtol=1e-12, atol=1e-14)
    assert orbit.converged
    c = 1 / (OMEGA**2 - 1 + 2j * ZETA)  # y = Re(c e^{i tau})
    np.testing.assert_allclose(orbit.y0, [c.real, (1j * c).real], atol=1e-10)
    np.testing.assert_allclose(orbit.monodromy, linalg.expm(2 * np.pi * A_LIN), atol=1e-10)
    # multipliers exp(2 pi lambda) with lambda the eigenvalues of A: modulus exp(-2 pi zeta)
    np.testing.assert_allclose(np.abs(orbit.multipliers), np.exp(-2 * np.pi * ZETA), rtol=1e-10)
    assert orbit.stable and orbit.liouville_error < 1e-10
    assert orbit.iterations == 1  # linear: Newton is exact in one step


def test_monodromy_of_model_9_matches_differences_of_the_period_map():
    P = get_preset("fig12").params
    model = SmoothModel(P)
    y0 = np.array([0.4, 0.1, 0.8, 0.9])
    yT, M, _ = period_map(model.rhs, model.jac, y0, 2 * np.pi, rtol=1e-12, atol=1e-13)
    h = 1e-6
    fd = np.column_stack([(period_map(model.rhs, model.jac, y0 + h * e, 2 * np.pi, rtol=1e-12, atol=1e-13)[0] - period_map(model.rhs, model.jac, y0 - h * e, 2 * np.pi, rtol=1e-12, atol=1e-13)[0]) / (2 * h) for e in np.eye(4)])
    np.testing.assert_allclose(M, fd, rtol=1e-5, atol=1e-5)


def test_fig10_resonant_orbit_exists_but_is_unstable():
    """The paper calls Fig. 10 a resonant periodic regime. Shooting on (9) finds the 2pi-periodic
    orbit near the simulated response, with a real Floquet multiplier ~16: unstable. (The long
    simulation does not settle on it: its stroboscopic state keeps wandering; see the issue notes.)
    """
    P = get_preset("fig10").params
    guess = np.array([-2.29697839, 0.4870925, 0.62950163, -1.6026986])  # a simulated state at tau = 200 pi
    orbit = periodic_orbit(P, guess, rtol=1e-10, atol=1e-12)
    assert orbit.converged and orbit.liouville_error < 1e-8
    assert abs(orbit.y0[0]) == pytest.approx(2.47, abs=0.02)
    assert abs(orbit.multipliers[0]) > 10 and not orbit.stable


def test_shooting_reports_non_convergence_instead_of_raising():
    P = get_preset("fig10").params
    orbit = periodic_orbit(P, [0.5, 0.0, 0.0, 0.1], max_iter=1)
    assert not orbit.converged and "no convergence in 1 Newton steps" in orbit.message
    with pytest.raises(ValueError, match="initial guess must be finite"):
        periodic_orbit(P, [np.nan, 0, 0, 0])
