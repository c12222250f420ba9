"""Models (8) and (9): generated derivatives, energy balance, and the impact law's bookkeeping."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from slosh_bif import ImpactModel, Params, SmoothModel, get_preset, simulate_impact
from slosh_bif.model.presets import uv_from_state
from slosh_bif.simulation.direct import integrate_smooth


def params(**changes):
    base = dict(eps=0.05, beta=0.3, gamma=0.2, sigma=1.0, Abar=1.0, lam=0.35, chi=0.2, n=6, pbar=0)
    return Params(**{**base, **changes})


@pytest.mark.parametrize("p", [params(), params(n=50, beta=0.0), params(n=6, pbar=-6, lam=0.05)])
def test_smooth_jacobian_matches_central_differences(p):
    model = SmoothModel(p)
    rng = np.random.default_rng(1)
    for _ in range(5):
        y = rng.uniform(-1.05, 1.05, size=4)
        tau = rng.uniform(0, 2 * np.pi)
        h = 1e-6
        fd = np.column_stack(
            [(model.rhs(tau, y + h * e) - model.rhs(tau, y - h * e)) / (2 * h) for e in np.eye(4)]
        )
        # Central differences: error ~ h**2 * f''' with f''' up to ~n**3 w**(2n-2) near the wall.
        np.testing.assert_allclose(model.jac(tau, y), fd, rtol=1e-6, atol=1e-6)


def test_variational_equations_give_the_derivative_of_the_flow_map():
    p = params(n=6)
    model = SmoothModel(p)
    y0, T = np.array([0.3, 0.5, 0.6, 1.1]), 2 * np.pi
    z0 = np.concatenate([y0, np.eye(4).ravel()])
    Phi = (
        solve_ivp(model.variational, (0, T), z0, method="DOP853", rtol=1e-12, atol=1e-13)
        .y[4:, -1]
        .reshape(4, 4)
    )

    def flow(y):
        return solve_ivp(model.rhs, (0, T), y, method="DOP853", rtol=1e-12, atol=1e-13).y[:, -1]

    h = 1e-5
    fd = np.column_stack([(flow(y0 + h * e) - flow(y0 - h * e)) / (2 * h) for e in np.eye(4)])
    # Central differences of a map integrated to 1e-12: error ~ h^2 |D^3 phi| + 1e-12/h ~ 1e-7 here.
    np.testing.assert_allclose(Phi, fd, rtol=1e-6, atol=1e-6)


def test_smooth_jacobian_is_finite_at_w_zero_when_p_is_zero():
    p = params(n=6, pbar=-6, lam=0.05)  # p = 0: linear damping lam*w'
    assert p.p == 0
    J = SmoothModel(p).jac(0.0, np.array([0.1, 0.2, 0.0, 0.3]))
    assert np.all(np.isfinite(J)) and J[3, 2] == pytest.approx(
        SmoothModel(p).jac(0.0, np.array([0.1, 0.2, 1e-12, 0.3]))[3, 2]
    )


def test_generated_functions_vectorise():
    model = SmoothModel(params())
    y = np.random.default_rng(2).uniform(-1, 1, size=(4, 7))
    tau = np.linspace(0, 1, 7)
    batch = model.rhs(tau, y)
    assert batch.shape == (4, 7)
    np.testing.assert_allclose(batch[:, 3], model.rhs(tau[3], y[:, 3]), rtol=1e-15)
    assert model.jac(tau, y).shape == (4, 4, 7)


def test_smooth_energy_is_conserved_without_forcing_and_damping():
    p = params(gamma=0.0, lam=0.0, Abar=0.0, n=6)
    model = SmoothModel(p)
    y0 = get_preset("fig10").state0
    traj = integrate_smooth(p, y0, (0, 200), rtol=1e-12, atol=1e-13, t_eval=np.linspace(0, 200, 401))
    H = model.energy(traj.y)
    # Tolerance: ~ steps * rtol * H for a non-symplectic DOP853 at rtol 1e-12.
    np.testing.assert_allclose(H, H[0], rtol=1e-9)


def test_smooth_energy_balance_with_forcing_damping_and_wall_dissipation():
    p = get_preset("fig12").params  # n = 6, gamma, lam, Abar all on
    model = SmoothModel(p)

    def augmented(tau, z):
        return np.append(model.rhs(tau, z[:4]), model.power(tau, z[:4]))

    y0 = get_preset("fig12").state0
    sol = solve_ivp(augmented, (0, 100), np.append(y0, 0.0), method="DOP853", rtol=1e-12, atol=1e-13)
    H0, H1 = model.energy(y0), model.energy(sol.y[:4, -1])
    work = sol.y[4, -1]
    assert abs(work) > 1e-2  # the balance is not trivially zero
    assert H1 - H0 == pytest.approx(work, abs=1e-9)


def test_impact_conserves_momentum_and_transmits_eq4():
    p = get_preset("fig10").params
    model = ImpactModel(p)
    before = np.array([0.3, -0.7, 1.0, 2.2])
    after = model.impact(before)
    kappa = model.kappa(2.2)
    eps = p.eps
    (u0, ud0, v0, vd0), (u1, ud1, v1, vd1) = uv_from_state(before, eps), uv_from_state(after, eps)
    # (3): M u' + m v' is unchanged (M = 1, m = eps); positions do not jump.
    assert ud1 + eps * vd1 == pytest.approx(ud0 + eps * vd0, abs=1e-15)
    assert (u1, v1) == pytest.approx((u0, v0), abs=1e-15)
    # (4): Delta P = M (u'+ - u'-) = -M m/(M+m) (kappa + 1) w'-.
    assert ud1 - ud0 == pytest.approx(-eps / (1 + eps) * (kappa + 1) * before[3], rel=1e-14)
    # (2): w'+ = -kappa w'-.
    assert after[3] == pytest.approx(-kappa * before[3], rel=1e-15)


def test_impact_energy_is_conserved_between_impacts_and_drops_by_the_restitution_loss():
    p = params(gamma=0.0, Abar=0.0, beta=0.3, n=50, pbar=2, lam=0.2)
    model = ImpactModel(p)
    traj = simulate_impact(p, [0.5, 0.8, 0.9, 1.5], (0, 80))
    assert traj.success and len(traj.impact_t) > 10
    H = model.energy(traj.y)
    for t_imp, v_minus, v_plus in zip(traj.impact_t, traj.impact_v_minus, traj.impact_v_plus):
        k = np.searchsorted(traj.t, t_imp)
        kappa = model.kappa(abs(v_minus))
        assert v_plus == pytest.approx(-kappa * v_minus, rel=1e-14)
        loss = 0.5 * model.weight * (1 - kappa**2) * v_minus**2
        assert H[k - 1] - H[k] == pytest.approx(loss, rel=1e-8, abs=1e-13)
    # Between impacts the energy is constant (the flow is exact): compare consecutive samples.
    impact_rows = set(np.searchsorted(traj.t, traj.impact_t))
    flat = [abs(H[i + 1] - H[i]) for i in range(len(H) - 1) if i + 1 not in impact_rows]
    assert max(flat) < 1e-12


def test_impact_model_between_impacts_matches_numerical_integration():
    p = params(lam=0.0)
    model = ImpactModel(p)
    y0 = np.array([0.2, 0.1, 0.0, 0.05])  # small motion: no impact in 20 time units
    traj = simulate_impact(p, y0, (0, 20))
    assert len(traj.impact_t) == 0
    ref = solve_ivp(model.rhs, (0, 20), y0, method="DOP853", rtol=1e-12, atol=1e-14, t_eval=traj.t)
    np.testing.assert_allclose(traj.y, ref.y, atol=1e-10)


def test_impacts_happen_on_the_walls_moving_outward():
    p = get_preset("fig10").params
    traj = simulate_impact(p, get_preset("fig10").state0, (0, 100))
    assert len(traj.impact_t) > 20
    assert np.all(traj.impact_side * traj.impact_v_minus > 0)
    assert np.all(np.abs(traj.y[2]) <= 1 + 1e-12)


def test_simulate_impact_rejects_bad_input():
    p = params()
    with pytest.raises(ValueError, match=r"\|w\| <= 1; got w = 1.5"):
        simulate_impact(p, [0, 0, 1.5, 0], (0, 1))
    with pytest.raises(ValueError, match="t_span must be finite with t1 > t0"):
        simulate_impact(p, [0, 0, 0, 0], (1, 0))
    with pytest.raises(ValueError, match="4 finite numbers"):
        simulate_impact(p, [0, 0, np.nan, 0], (0, 1))
    with pytest.raises(ValueError, match=r"sample_step must be in \(0, 0.5\]"):
        simulate_impact(p, [0, 0, 0, 0], (0, 1), sample_step=2.0)
