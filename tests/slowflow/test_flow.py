"""The derived slow flow (36), (39), (42), (43), (45), (46) against independent evaluations and the full
models."""

import numpy as np
import pytest
from scipy import integrate, optimize

from slosh_bif import get_preset, simulate_impact
from slosh_bif.model import manifold, restitution
from slosh_bif.model.manifold import project_on_manifold
from slosh_bif.simulation.direct import integrate_smooth
from slosh_bif.slowflow.flow import SlowFlow

FIG10 = get_preset("fig10").params


def flows():
    yield SlowFlow(FIG10)  # Newtonian, rho constant
    yield SlowFlow(FIG10.replace(beta=0.3, pbar=2, lam=0.25, chi=1.0))  # rho(A) through eq. (39)
    yield SlowFlow(FIG10.replace(n=6, pbar=-2, lam=0.25, chi=1.0, sigma=-0.5))


@pytest.mark.parametrize("flow", list(flows()), ids=["newtonian", "pbar=2", "n=6,pbar=-2"])
def test_slow_jacobian_matches_central_differences(flow):
    # The A-derivative includes d rho/dA from implicit differentiation of (39): FD of rhs checks it too.
    for A, psi in [(0.8, 0.3), (1.7, -2.0), (3.0, 1.0)]:
        h = 1e-6 * A
        fd_A = (flow.rhs(A + h, psi) - flow.rhs(A - h, psi)) / (2 * h)
        fd_psi = (flow.rhs(A, psi + 1e-6) - flow.rhs(A, psi - 1e-6)) / 2e-6
        np.testing.assert_allclose(flow.jac(A, psi), np.column_stack([fd_A, fd_psi]), rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("flow", list(flows()), ids=["newtonian", "pbar=2", "n=6,pbar=-2"])
def test_steady_residual_gradient_matches_central_differences(flow):
    P = flow.params
    for A in (0.9, 2.2):
        grad = flow.steady_residual_grad(A)
        h = 1e-6
        fd = [
            (flow.steady_residual(A + h * A) - flow.steady_residual(A - h * A)) / (2 * h * A),
            (flow.steady_residual(A, sigma=P.sigma + h) - flow.steady_residual(A, sigma=P.sigma - h))
            / (2 * h),
            (flow.steady_residual(A, Abar=P.Abar + h) - flow.steady_residual(A, Abar=P.Abar - h)) / (2 * h),
        ]
        np.testing.assert_allclose(grad, fd, rtol=1e-6)


def test_fourier_series_matches_quadrature_of_the_triangle_wave():
    """(42) as derived: a_k = 8 alpha/(pi^2 k^2) for odd k, 0 for even k, all positive."""
    alpha, eta = 0.8, 0.4
    f = lambda T0: 2 * alpha / np.pi * np.arcsin(np.cos(T0 - eta))  # noqa: E731 - the paper's (29)
    for k in range(1, 8):
        a_k = (
            integrate.quad(
                lambda T0: f(T0) * np.cos(k * (T0 - eta)),
                eta - np.pi,
                eta + np.pi,
                points=[eta],
                epsabs=1e-13,
            )[0]
            / np.pi
        )
        b_k = (
            integrate.quad(
                lambda T0: f(T0) * np.sin(k * (T0 - eta)),
                eta - np.pi,
                eta + np.pi,
                points=[eta],
                epsabs=1e-13,
            )[0]
            / np.pi
        )
        expected = 8 * alpha / (np.pi**2 * k**2) if k % 2 else 0.0
        assert a_k == pytest.approx(expected, abs=1e-12)
        assert b_k == pytest.approx(0.0, abs=1e-12)


def test_manifold_roots_satisfy_the_impact_conditions():
    """Both branches of (36) solve (31)-(32): (rho alpha)^2 + (1 - alpha)^2 = A^2; the end is the fold."""
    for rho in (0.05, 0.3, 0.6):
        A = np.linspace(manifold.a_min(rho), 4, 50)
        for branch in (manifold.STABLE, manifold.UNSTABLE):
            a = manifold.alpha(A, rho, branch)
            np.testing.assert_allclose((rho * a) ** 2 + (1 - a) ** 2, A**2, rtol=1e-12, atol=1e-14)
        # Independent closed forms typed from the derivation: A_min = rho/sqrt(1+rho^2), alpha_min =
        # 1/(1+rho^2).
        assert manifold.a_min(rho) == pytest.approx(rho / np.sqrt(1 + rho**2), rel=1e-15)
        assert manifold.alpha(manifold.a_min(rho), rho) == pytest.approx(1 / (1 + rho**2), rel=1e-12)
        assert manifold.alpha(manifold.a_min(rho), rho, manifold.UNSTABLE) == pytest.approx(
            1 / (1 + rho**2), rel=1e-12
        )
    with pytest.raises(ValueError, match="must be >= A_min"):
        manifold.alpha(0.01, 0.3)


def test_steady_states_of_46_are_equilibria_of_45():
    flow = SlowFlow(FIG10)
    grid = np.linspace(flow.A_min * 1.001, 10, 4000)
    r = flow.steady_residual(grid)
    roots = [
        optimize.brentq(flow.steady_residual, grid[i], grid[i + 1], xtol=1e-14)
        for i in np.nonzero(np.diff(np.sign(r)))[0]
    ]
    assert roots
    for A in roots:
        np.testing.assert_allclose(flow.rhs(A, flow.steady_phase(A)), [0, 0], atol=1e-10)


def test_manifold_end_is_self_consistent_for_velocity_dependent_restitution():
    P = FIG10.replace(pbar=2, lam=0.25, chi=1.0)
    flow = SlowFlow(P)
    # The fold is a square root: rounding (1e-16) in alpha becomes ~1e-8 in A there, so probe at 1e-6.
    above = restitution.kappa_on_manifold(flow.A_min * (1 + 1e-6), P.lam, P.chi, P.n, P.pbar, strict=False)
    below = restitution.kappa_on_manifold(flow.A_min * (1 - 1e-6), P.lam, P.chi, P.n, P.pbar, strict=False)
    assert above.exists and not below.exists
    assert float(above.kappa) == pytest.approx(flow.kappa_at_end, abs=1e-5)


def test_projection_recovers_amplitudes_of_a_synthetic_manifold_motion():
    A, alpha, eta = 1.3, 1.6, 0.7
    t = np.linspace(0, 20 * np.pi, 40001)
    X = A * np.sin(t + 0.2)
    f = 2 * alpha / np.pi * np.arcsin(np.cos(t - eta))
    y = np.vstack([X, np.gradient(X, t), X + f, np.zeros_like(t)])
    proj = project_on_manifold(t, y)
    # Peaks are read off samples: the error is at most slope * step / 2 (|f'| = 2 alpha/pi, step 1.6e-3).
    step = t[1] - t[0]
    np.testing.assert_allclose(proj.A, A, atol=A * step**2)
    np.testing.assert_allclose(proj.alpha, alpha, atol=2 * alpha / np.pi * step / 2)


# --- settling the printed (43) and (46) with the full models -------------------------------------


def _printed_43_decay(flow, A0, T1):
    """D1 A of the printed (43), with its extra factor rho, integrated from A0 (independent code)."""
    rho = flow.rho(A0)[0]
    P = flow.params

    def rhs(_t, a):
        alpha = manifold.alpha(max(a[0], flow.A_min), rho)
        return [-P.gamma * a[0] / 2 - 4 * rho * alpha**2 * (1 - P.beta**2) * rho / (np.pi**2 * a[0])]

    return integrate.solve_ivp(rhs, (T1[0], T1[-1]), [A0], t_eval=T1, rtol=1e-10).y[0]


@pytest.mark.parametrize("name", ["fig9a", "fig9b"])
def test_free_slow_flow_follows_the_vibro_impact_model(name):
    """(43) as derived against a direct simulation of (8) at the Fig. 9 parameters.

    First-order multiple scales errs by O(eps) on slow times T1 = O(1): up to T1 = 5 (tau = 100)
    we allow 1.5 eps (measured: 3.7 % at beta = 0, 1.9 % at beta = 0.3, eps = 0.05). The escape
    from the manifold (A reaching A_min; in the simulation, A falling below 2 A_min) is predicted
    within 15 % (measured 9 % at beta = 0, 3 % at beta = 0.3).
    """
    preset = get_preset(name)
    P = preset.params
    sim = simulate_impact(P, preset.state0, (0, 600), sample_step=0.02)
    proj = project_on_manifold(sim.t, sim.y)
    flow = SlowFlow(P)
    early = proj.t <= 5 / P.eps
    slow = flow.integrate(proj.A[0], 0.0, (P.eps * proj.t[0], P.eps * 600), t_eval=P.eps * proj.t[early])
    rel = np.abs(slow.A - proj.A[early]) / proj.A[early]
    assert rel.max() < 1.5 * P.eps
    assert slow.escaped
    t_escape_slow = slow.T1_end / P.eps
    t_escape_sim = proj.t[np.argmax(proj.A < 2 * flow.A_min)]
    assert t_escape_slow == pytest.approx(t_escape_sim, rel=0.15)
    # The printed (43) decays ~1/rho = 15 times too slowly: by tau = 100 it errs by 25 % (beta = 0.3)
    # to 30 % (beta = 0), over three times the tolerance the derived flow meets.
    printed = _printed_43_decay(flow, proj.A[0], P.eps * proj.t[early])
    assert np.max(np.abs(printed - proj.A[early]) / proj.A[early]) > 3 * 1.5 * P.eps


def _state_on_manifold(flow, A, psi, tau=0.0):
    """[X, X', w, w'] at tau of the steady 1:1 motion of amplitude A and phase psi on S+."""
    rho = float(flow.rho(A)[0])
    alpha = float(flow.alpha(A))
    phase = np.arctan2((1 - alpha) / A, rho * alpha)  # eta + psi from (31)-(32)
    eta = phase - psi
    X, Xd = A * np.sin(tau + psi), A * np.cos(tau + psi)
    f = 2 * alpha / np.pi * np.arcsin(np.cos(tau - eta))
    fd = -2 * alpha / np.pi * np.sign(np.sin(tau - eta))
    return np.array([X, Xd, np.clip(X + f, -0.999, 0.999), Xd + fd])


def _printed_46_states(flow, sigma):
    """Steady amplitudes on S+ of the printed (46) (minus sign in the first bracket), independent code."""
    P = flow.params
    rho = float(flow.rho(1.0)[0])

    def residual(A):
        a = manifold.alpha(A, rho)
        return (
            (P.gamma * np.pi**2 * A**2 - 8 * rho * a**2 * (1 - P.beta**2)) ** 2
            + (np.pi**2 * (sigma - (1 - P.beta**2)) * A**2 - 8 * a * (1 - a) * (1 - P.beta**2)) ** 2
            - np.pi**4 * A**2 * P.Abar**2
        )

    grid = np.linspace(flow.A_min * 1.001, 10, 20001)
    r = residual(grid)
    return [optimize.brentq(residual, grid[i], grid[i + 1]) for i in np.nonzero(np.diff(np.sign(r)))[0]]


def test_eq46_sign_settled_on_the_smooth_model():
    """At the Fig. 10 set with Abar = 0.5 the two signs of (46) predict different response curves.

    The printed sign has a stable-branch state at A ~ 4.25 for sigma = 0; the derived sign has
    none there. The smooth model (9), started on the printed state, leaves it (A falls below 1);
    started on the derived peak state at sigma = -0.39, it stays within 10 % (eq. 21's error in
    kappa at n = 50, 4 %, and O(eps) account for the rest).
    """
    base = FIG10.replace(Abar=0.5)
    at_zero = SlowFlow(base.replace(sigma=0.0))
    printed = _printed_46_states(at_zero, 0.0)
    assert max(printed) == pytest.approx(4.25, abs=0.01)
    assert np.all(
        at_zero.steady_residual(np.linspace(at_zero.A_min * 1.001, 10, 5000)) > 0
    )  # derived: no state
    run = integrate_smooth(
        base.replace(sigma=0.0),
        _state_on_manifold(at_zero, max(printed), 0.0),
        (0, 600),
        rtol=1e-8,
        atol=1e-10,
        t_eval=np.linspace(400, 600, 4001),
    )
    assert np.abs(run.y[0]).max() < 1.0

    peak = SlowFlow(base.replace(sigma=-0.39))
    grid = np.linspace(peak.A_min * 1.001, 10, 20001)
    r = peak.steady_residual(grid)
    A_derived = max(
        optimize.brentq(peak.steady_residual, grid[i], grid[i + 1])
        for i in np.nonzero(np.diff(np.sign(r)))[0]
    )
    assert A_derived == pytest.approx(1.39, abs=0.01)
    start = _state_on_manifold(peak, A_derived, float(peak.steady_phase(A_derived)))
    run = integrate_smooth(
        peak.params, start, (0, 600), rtol=1e-8, atol=1e-10, t_eval=np.linspace(400, 600, 4001)
    )
    assert np.abs(run.y[0]).max() == pytest.approx(A_derived, rel=0.10)


@pytest.mark.parametrize("flow", list(flows())[:2], ids=["newtonian", "pbar=2"])
def test_fast_state_touches_both_walls_with_the_impact_speed_of_eq_38(flow):
    # The leading-order motion (25), (29), (35) on S+ reaches w = +1 and w = -1 once each per
    # period (conditions 31, 32) and arrives there at speed alpha (2/pi + rho), eq. (38).
    A, psi = 1.3, 0.4
    tau = np.linspace(0, 2 * np.pi, 200001)
    y = flow.fast_state(A, psi, tau)
    np.testing.assert_allclose(y[:, 0], A * np.sin(tau + psi), atol=1e-14)
    # Never beyond a wall, and within a grid step's travel (3e-5 * speed) of each.
    assert abs(y[:, 2]).max() <= 1 + 1e-12
    assert y[:, 2].max() == pytest.approx(1.0, abs=1e-4) and y[:, 2].min() == pytest.approx(-1.0, abs=1e-4)
    alpha, rho = float(flow.alpha(A)), float(flow.rho(A)[0])
    hit = int(np.argmax(y[:, 2]))
    assert y[hit - 1, 3] == pytest.approx(alpha * (2 / np.pi + rho), rel=1e-3)
    with pytest.raises(ValueError, match="A_min"):
        flow.fast_state(0.5 * flow.A_min, psi, tau)
