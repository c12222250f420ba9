"""Frequency-response curves and the critical forcing, checked against the closed forms of (46)."""

import numpy as np
import pytest
from scipy import optimize
from scipy.integrate import solve_ivp

from slosh_bif import get_preset
from slosh_bif.continuation.branch import Branch
from slosh_bif.model import restitution
from slosh_bif.slowflow.critical import critical_curve, critical_forcing
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.slowflow.steady_states import frequency_response

FIG10, FIG13 = get_preset("fig10").params, get_preset("fig13").params


# Independent closed forms, typed from the derivation (not the generated code).
def rho_of(P, A):
    if P.pbar == 0:
        return float(restitution.rho(restitution.kappa_newtonian(P.lam, P.chi, P.n)))
    return float(restitution.kappa_on_manifold(A, P.lam, P.chi, P.n, P.pbar).rho)


def alpha_of(A, rho):
    # at the end A = A_min exactly the square root's argument is zero up to rounding
    return (1 + np.sqrt(np.maximum((1 + rho**2) * A**2 - rho**2, 0.0))) / (1 + rho**2)


def E_Phi(P, A, sigma):
    rho = rho_of(P, A)
    a = alpha_of(A, rho)
    c = 1 - P.beta**2
    return P.gamma * np.pi**2 * A**2 + 8 * rho * a**2 * c, np.pi**2 * (sigma - c) * A**2 - 8 * a * (1 - a) * c


def abar_closed(P, A, sigma):
    E, Phi = E_Phi(P, A, sigma)
    return np.hypot(E, Phi) / (np.pi**2 * A)


def sigma_roots_closed(P, A):
    """(46) is quadratic in sigma at fixed A."""
    E, Phi0 = E_Phi(P, A, 0.0)
    root = np.sqrt(np.pi**4 * A**2 * P.Abar**2 - E**2)
    return (-Phi0 - root) / (np.pi**2 * A**2), (-Phi0 + root) / (np.pi**2 * A**2)


CASES = [FIG10, FIG13, FIG13.replace(pbar=2, lam=0.25, chi=1.0), get_preset("fig12").params.replace(Abar=1.2)]
IDS = ["fig10", "fig13", "fig13-pbar2", "fig12-Abar1.2"]


@pytest.mark.parametrize("P", CASES, ids=IDS)
def test_every_point_satisfies_eq46_in_closed_form(P):
    fr = frequency_response(P, sigma_min=-6, sigma_max=8)
    assert fr.branches
    for branch in fr.branches:
        for (A, _), sigma in zip(branch.x, branch.p):
            E, Phi = E_Phi(P, A, sigma)
            scale = np.pi**4 * A**2 * P.Abar**2
            assert abs(E**2 + Phi**2 - scale) <= 1e-10 * scale
            # and sigma is one of the two roots of the quadratic, to the same accuracy
            assert min(abs(sigma - r) for r in sigma_roots_closed(P, A)) <= 1e-9 * max(1, abs(sigma))


def test_folds_are_the_extrema_of_sigma_of_A_to_1e_8():
    P = FIG13
    fr = frequency_response(P)  # the full curve: its fold lies near sigma = -13
    folds = [s for b in fr.branches for s in b.special_of("LP")]
    assert len(folds) == 1
    A_fold = folds[0].x[0]
    # A fold in sigma is a local extremum of one root sigma(A) of the quadratic: find it independently.
    extrema = []
    for root in (0, 1):
        for sign in (1, -1):
            res = optimize.minimize_scalar(
                lambda A: sign * sigma_roots_closed(P, A)[root],
                bounds=(0.9 * A_fold, 1.1 * A_fold),
                method="bounded",
                options={"xatol": 1e-12},
            )
            if 0.91 * A_fold < res.x < 1.09 * A_fold:  # interior: a true extremum
                extrema.append(sign * res.fun)
    assert len(extrema) == 1
    assert folds[0].p == pytest.approx(extrema[0], abs=1e-8)


def test_branch_ends_on_the_manifold_end_not_on_the_unstable_branch():
    fr = frequency_response(FIG10)
    ends = [s for b in fr.branches for s in b.special_of("END")]
    assert len(ends) == 2
    A_min = SlowFlow(FIG10).A_min
    rho = rho_of(FIG10, 1.0)
    assert A_min == pytest.approx(rho / np.sqrt(1 + rho**2), rel=1e-15)  # (36), closed form
    for end in ends:
        assert "manifold end (36)" in end.message and end.reason == "domain edge"
        assert end.x[0] == A_min  # exactly on the end, not a margin inside it
        # (46) at the end, with alpha = alpha_min = 1/(1 + rho^2) typed from (36), to 1e-10
        a, c = 1 / (1 + rho**2), 1 - FIG10.beta**2
        E = FIG10.gamma * np.pi**2 * A_min**2 + 8 * rho * a**2 * c
        Phi = np.pi**2 * (end.p - c) * A_min**2 - 8 * a * (1 - a) * c
        assert np.hypot(E, Phi) == pytest.approx(np.pi**2 * A_min * FIG10.Abar, rel=1e-10)
    assert all(np.all(b.x[:, 0] >= A_min) for b in fr.branches)


def _kick_grows(flow, A, psi, sigma):
    """Kick the equilibrium along its least stable eigenvector and integrate the slow flow (45).

    Returns True when the kick grows tenfold or the motion reaches the manifold's end, False
    when it decays: an independent reading of stability from the dynamics themselves.
    """
    w, v = np.linalg.eig(flow.jac(A, psi, sigma=sigma))
    size = 1e-3 * (A - flow.A_min)
    kick = size * np.real(v[:, np.argmax(w.real)]) / np.linalg.norm(np.real(v[:, np.argmax(w.real)]))

    def off_manifold(t, z):
        return z[0] - flow.A_min * (1 + 1e-6)

    off_manifold.terminal = True
    T = 5 / max(abs(w.real.max()), 1e-3)  # five e-foldings of the least stable mode
    sol = solve_ivp(
        lambda t, z: flow.rhs(max(z[0], flow.A_min * (1 + 1e-6)), z[1], sigma=sigma),
        (0, T),
        [A + kick[0], psi + kick[1]],
        events=off_manifold,
        rtol=1e-11,
        atol=1e-14,
    )
    return sol.status == 1 or np.hypot(sol.y[0, -1] - A, sol.y[1, -1] - psi) > 10 * size


@pytest.mark.parametrize(
    "P", [FIG13, get_preset("fig12").params.replace(Abar=1.2)], ids=["fig13", "fig12-Abar1.2"]
)
def test_stability_labels_agree_with_integrating_the_slow_flow(P):
    fr = frequency_response(P)
    flow = SlowFlow(P)
    branch = fr.branches[0]
    checked = set()
    for a, b in _stability_runs(branch.stable):
        if b - a < 2:
            continue
        i = (a + b) // 2  # the middle of a run of equal stability
        A, psi = branch.x[i]
        assert _kick_grows(flow, A, psi, branch.p[i]) == (not branch.stable[i]), (branch.p[i], A)
        checked.add(bool(branch.stable[i]))
    assert checked == {True, False}


def _stability_runs(stable):
    change = np.flatnonzero(np.diff(stable.astype(int))) + 1
    bounds = np.concatenate([[0], change, [len(stable)]])
    return list(zip(bounds[:-1], bounds[1:] - 1))


@pytest.mark.parametrize("sigma", [-2.0, 0.0, 1.0, 3.0])
def test_critical_forcing_is_the_minimum_of_abar_over_A(sigma):
    P = FIG13
    cp = critical_forcing(P, sigma)
    A_min = SlowFlow(P).A_min
    grid = np.concatenate([[A_min], np.geomspace(A_min * (1 + 1e-8), 20, 20000)])
    values = np.array([abar_closed(P, A, sigma) for A in grid])
    k = int(np.argmin(values))
    if k <= 1:  # the end itself: (46) in closed form at A = A_min, alpha = alpha_min
        expected, kind = values[0], "END"
    else:
        res = optimize.minimize_scalar(
            lambda A: abar_closed(P, A, sigma), bracket=(grid[k - 1], grid[k], grid[k + 1]), tol=1e-12
        )
        expected, kind = res.fun, "LP"
    assert cp.kind == kind
    assert cp.Abar_b == pytest.approx(expected, rel=1e-10 if kind == "END" else 1e-8)


def test_critical_curve_matches_the_pointwise_critical_forcing():
    P = FIG13
    curve = critical_curve(P, -3.0, 4.0)
    assert set(curve.kind) == {"LP", "END"} and np.all(np.diff(curve.sigma) >= 0)
    # At the curve's own sigmas, the two-parameter continuation and the pointwise minimum agree to 1e-8.
    for i in np.linspace(0, len(curve.sigma) - 1, 9).astype(int):
        assert curve.Abar_b[i] == pytest.approx(critical_forcing(P, curve.sigma[i]).Abar_b, abs=1e-8)
    # every curve point is exact: R = 0 at its (A, sigma, Abar) in closed form
    for sigma, Abar_b, A in zip(curve.sigma, curve.Abar_b, curve.A):
        assert abar_closed(P, A, sigma) == pytest.approx(Abar_b, rel=1e-9)


def test_presets_agree_with_the_paper_regimes():
    """Fig. 12 (Abar = 0.5) is strongly modulated: no steady state; Figs. 10 and 13 settle on one."""
    assert critical_forcing(get_preset("fig12").params, 1.0).Abar_b > 0.5
    assert critical_forcing(FIG13, 1.0).Abar_b < 1.0
    assert critical_forcing(FIG10, 1.0).Abar_b < 3.0


def test_frequency_response_rejects_unforced_and_subcritical_input():
    with pytest.raises(ValueError, match="parameter Abar must be > 0"):
        frequency_response(FIG10.replace(Abar=0.0))
    with pytest.raises(ValueError, match="no steady state on the stable manifold branch"):
        frequency_response(FIG10.replace(Abar=0.01))


def test_frc_branch_round_trips(tmp_path):
    branch = frequency_response(FIG13, sigma_min=-3, sigma_max=3).branches[0]
    loaded = Branch.load(branch.save(tmp_path / "b.npz"))
    np.testing.assert_array_equal(loaded.x, branch.x)
    np.testing.assert_array_equal(loaded.stable, branch.stable)
    assert loaded.special_labels() == branch.special_labels()


HELD_OUT_WALL = dict(lam=0.5, chi=2, n=8, pbar=4, beta=0.1, Abar=1.5)  # S+ ends above at a fold of (39)


def test_the_upper_end_condition_and_the_fold_curves_stay_on_s_plus():
    """The end condition on the upper end of S+ gives the forcing of the steady state there by
    (46)'s balances; fold curves are never evaluated past that end (they were, and failed)."""
    from slosh_bif.slowflow.critical import EndProblem, FoldProblem, abar_at_upper_end

    P = get_preset("fig10").params.replace(**HELD_OUT_WALL)
    for sigma in (-1.0, 0.5, 2.0):
        flow = SlowFlow(P.replace(sigma=sigma))
        assert EndProblem(P, end="upper").abar_at(sigma) == pytest.approx(
            abar_at_upper_end(flow, flow.A_max), rel=1e-9
        )
    folds = FoldProblem(P)
    assert not folds.in_domain(np.array([folds.r.flow.A_max * (1 + 1e-6), 1.0]), 0.0)
    assert folds.in_domain(np.array([folds.r.flow.A_max * 0.5, 1.0]), 0.0)


@pytest.mark.filterwarnings("ignore:slow flow outside its checked range")
def test_at_a_fold_of_s_plus_the_unused_infinite_slope_raises_no_numpy_warning():
    """At the fold of (39) that ends S+ above, R_A is infinite and rounding can put the root
    under it below zero (a NaN): the end's R, R_sigma and R_Abar are used, and no warning about
    R_A reaches the user (a random admissible set where it did at sigma = -4)."""
    import warnings

    from slosh_bif.model.params import Params
    from slosh_bif.slowflow.critical import EndProblem, abar_at_upper_end

    P = Params(
        eps=0.09876011384422585,
        beta=0.5823508928063189,
        gamma=0.09009404281499403,
        sigma=0.0,
        Abar=2.1875717149225897,
        lam=0.3927080668452921,
        chi=0.8080862068317072,
        n=10,
        pbar=2,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        end = EndProblem(P, end="upper")
        at = end.abar_at(-4.0)
    flow = SlowFlow(P.replace(sigma=-4.0))
    assert at == pytest.approx(abar_at_upper_end(flow, flow.A_max), rel=1e-9)


@pytest.mark.slow
def test_critical_curve_reaches_an_upper_end_of_s_plus():
    """A wall whose S+ ends above at a fold of (39): the curve is traced up to that end, and agrees
    with the one-sigma minimisation over S+ at every sigma of the range (a held-out wall)."""
    P = get_preset("fig10").params.replace(**HELD_OUT_WALL)
    curve = critical_curve(P, -2.0, 3.0)
    assert curve.upper_end_branch is not None and len(curve.upper_end_branch) > 2
    assert curve.sigma[0] == -2.0 and curve.sigma[-1] == 3.0
    for sigma, abar in zip(curve.sigma[::5], curve.Abar_b[::5]):
        assert abar == pytest.approx(critical_forcing(P, sigma).Abar_b, rel=1e-7)


def test_a_forcing_response_whose_whole_curve_lies_in_the_range_is_traced():
    """pbar = 3 (a random draw): S+ ends at the fold of (39), so every A on it has its Abar inside
    [0, 4.84]; the curve is one branch all the same, and at Abar = 1.5 it holds the steady states
    that the frequency response in sigma at that Abar has at the set's sigma (two runs in
    different parameters)."""
    from slosh_bif.slowflow.steady_states import forcing_response

    P = get_preset("fig10").params.replace(
        eps=0.07, beta=0.015, gamma=0.13, Abar=2.42, lam=0.353, chi=1.1, n=3, pbar=3
    )
    in_abar = forcing_response(P, abar_min=0.0, abar_max=2 * P.Abar)
    assert len(in_abar.branches) == 1 and len(in_abar.branches[0]) > 10
    in_sigma = frequency_response(P.replace(Abar=1.5), sigma_min=0.5, sigma_max=1.5)
    expected = sorted(A for b in in_sigma.branches for A in _crossings(b.p, b.x[:, 0], P.sigma))
    got = sorted(A for b in in_abar.branches for A in _crossings(b.p, b.x[:, 0], 1.5))
    assert len(got) == len(expected) >= 1
    np.testing.assert_allclose(got, expected, rtol=2e-2)  # read between points up to 0.2 apart


def _crossings(p, A, value):
    """A where the polyline (p, A) crosses p = value (linear between points)."""
    out = []
    for k in np.flatnonzero(np.diff(np.sign(p - value)) != 0):
        w = (value - p[k]) / (p[k + 1] - p[k])
        out.append(float(A[k] + w * (A[k + 1] - A[k])))
    return out
