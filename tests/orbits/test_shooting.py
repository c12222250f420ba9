"""Shooting and the compiled integrator: closed forms, differences, scipy, long simulation, failures."""

import numpy as np
import pytest
from scipy import linalg

from slosh_bif import SmoothModel, get_preset
from slosh_bif.continuation import ContinuationOptions, continuation
from slosh_bif.flows.smooth import integrator
from slosh_bif.orbits.orbit_tools import orbit_at, orbit_measures, periodic_orbit
from slosh_bif.orbits.shooting import PARAMETERS, ShootingProblem, period_map, shoot

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
    fd = np.column_stack(
        [
            (
                period_map(model.rhs, model.jac, y0 + h * e, 2 * np.pi, rtol=1e-12, atol=1e-13)[0]
                - period_map(model.rhs, model.jac, y0 - h * e, 2 * np.pi, rtol=1e-12, atol=1e-13)[0]
            )
            / (2 * h)
            for e in np.eye(4)
        ]
    )
    np.testing.assert_allclose(M, fd, rtol=1e-5, atol=1e-5)


def test_fig10_resonant_orbit_exists_but_is_unstable(scipy_flow):
    """The paper calls Fig. 10 a resonant periodic regime. Shooting on (9) finds the 2pi-periodic
    orbit near the simulated response, with a real Floquet multiplier ~16: unstable. (The long
    simulation does not settle on it: its stroboscopic state keeps wandering; see the issue notes.)
    """
    P = get_preset("fig10").params
    guess = np.array([-2.29697839, 0.4870925, 0.62950163, -1.6026986])  # a simulated state at tau = 200 pi
    orbit = periodic_orbit(P, guess, rtol=1e-10, atol=1e-12)
    assert orbit.converged and orbit.liouville_error < 1e-8
    y_T, monodromy = scipy_flow(P, orbit.y0)
    np.testing.assert_allclose(y_T, orbit.y0, atol=1e-7)  # 2pi-periodic by scipy's integrator too
    np.testing.assert_allclose(
        np.sort(np.abs(orbit.multipliers)), np.sort(np.abs(np.linalg.eigvals(monodromy))), rtol=1e-6
    )
    assert abs(orbit.multipliers[0]) > 10 and not orbit.stable


def test_shooting_reports_non_convergence_instead_of_raising():
    P = get_preset("fig10").params
    orbit = periodic_orbit(P, [0.5, 0.0, 0.0, 0.1], max_iter=1)
    assert not orbit.converged and "no convergence in 1 Newton steps" in orbit.message
    with pytest.raises(ValueError, match="initial guess must be finite"):
        periodic_orbit(P, [np.nan, 0, 0, 0])


# -- the compiled integrator and the shooting problem -------------------------------------------


# The compiled backend is a capability of the package: the test extra installs numba, so these
# tests run it (without numba they fail, naming the missing extra).
@pytest.mark.parametrize("preset", ["fig10", "fig12"])
def test_compiled_integrator_takes_scipys_steps_and_agrees_with_it(preset):
    """Same method, coefficients and step control as scipy's DOP853: the same number of accepted
    steps up to 2 % and the same end state up to rounding, on (9) alone and on the 29-dimensional
    shooting system. Not step for step: the compiled loop sums the stages in its own order (row
    by row, zero coefficients skipped), and through the n = 50 wall an accept or reject can turn
    on the last bit (250 against 252 steps at fig10; scipy releases differ by as much)."""
    P = get_preset(preset).params
    y0 = get_preset(preset).state0
    z0 = np.concatenate([y0, np.eye(4).ravel(), np.zeros(9)])
    for state, shooting in ((y0, False), (z0, True)):
        fast = integrator.integrate(P, state, (0.0, 2 * np.pi), shooting=shooting, backend="numba")
        slow = integrator.integrate(P, state, (0.0, 2 * np.pi), shooting=shooting, backend="scipy")
        assert fast.success and slow.success
        assert abs(fast.steps - slow.steps) <= max(2, 0.02 * slow.steps), (fast.steps, slow.steps)
        np.testing.assert_allclose(fast.z, slow.z, rtol=1e-7, atol=1e-8)


def test_compiled_integrator_converges_to_a_tight_reference():
    """Error after one period falls with the tolerance (against rtol = 1e-13)."""
    P = get_preset("fig12").params
    y0 = get_preset("fig12").state0
    ref = integrator.integrate(P, y0, (0.0, 2 * np.pi), rtol=1e-13, atol=1e-15).z
    errors = [
        np.max(np.abs(integrator.integrate(P, y0, (0.0, 2 * np.pi), rtol=r, atol=r * 1e-2).z - ref))
        for r in (1e-6, 1e-8, 1e-10)
    ]
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-8


def test_integrator_rejects_bad_input_before_work():
    P = get_preset("fig12").params
    with pytest.raises(ValueError, match="initial state must be 4 finite numbers"):
        integrator.integrate(P, [0, 0, np.inf, 0], (0, 1))
    with pytest.raises(ValueError, match="tau0 < tau1"):
        integrator.integrate(P, [0, 0, 0, 0], (1, 0))
    with pytest.raises(ValueError, match="backend must be"):
        integrator.integrate(P, [0, 0, 0, 0], (0, 1), backend="rk4")


def test_shooting_sensitivities_match_differences_in_sigma_and_abar():
    P = get_preset("fig12").params
    x = np.array([0.4, 0.1, 0.8, 0.9, -0.3, 0.2, -0.7, 0.5])
    for param in ("sigma", "Abar"):
        problem = ShootingProblem(P, param, segments=2, rtol=1e-12, atol=1e-13)
        p0, h = getattr(P, param), 1e-5
        fd = (problem.residual(x, p0 + h) - problem.residual(x, p0 - h)) / (2 * h)
        np.testing.assert_allclose(problem.dparam(x, p0), fd, rtol=1e-6, atol=1e-7)


def test_shooting_jacobian_and_both_sensitivities_match_differences_of_the_residual():
    # The block-cyclic Jacobian (arc matrices from the variational equations) and d/d(sigma, Abar)
    # from the sensitivity equations, against central differences of the residual itself.
    P = get_preset("fig12").params
    x = np.array([0.4, 0.1, 0.8, 0.9, -0.3, 0.2, -0.7, 0.5])
    problem = ShootingProblem(P, "sigma", segments=2, rtol=1e-12, atol=1e-13)
    J, h = problem.jacobian(x, P.sigma), 1e-6
    fd = np.column_stack(
        [
            (problem.residual(x + h * e, P.sigma) - problem.residual(x - h * e, P.sigma)) / (2 * h)
            for e in np.eye(len(x))
        ]
    )
    np.testing.assert_allclose(J, fd, rtol=1e-5, atol=1e-6)
    both = problem.dparams(x, P.sigma)
    for column, name in enumerate(("sigma", "Abar")):
        v = getattr(P, name)
        plus, minus = P.replace(**{name: v + 1e-5}), P.replace(**{name: v - 1e-5})
        fd = (
            problem.residual_of(x, problem.arcs(x, plus)) - problem.residual_of(x, problem.arcs(x, minus))
        ) / 2e-5
        np.testing.assert_allclose(both[:, column], fd, rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize("name", PARAMETERS)
def test_sensitivities_in_every_real_parameter_match_differences_of_scipys_flow(name, scipy_flow):
    # The generated pair kernel (any parameter but the (sigma, Abar) pair's own kernel) against
    # central differences of scipy's period map of SmoothModel (no generated shooting kernel).
    P = get_preset("fig12").params
    y0 = np.array([0.4, 0.1, 0.8, 0.9])
    problem = ShootingProblem(P, name, rtol=1e-12, atol=1e-13)
    v, h = getattr(P, name), 1e-5 * max(1.0, abs(getattr(P, name)))
    fd = (scipy_flow(P.replace(**{name: v + h}), y0)[0] - scipy_flow(P.replace(**{name: v - h}), y0)[0]) / (
        2 * h
    )
    np.testing.assert_allclose(problem.dparam(y0, v), fd, rtol=1e-6, atol=1e-7)
    assert np.max(np.abs(fd)) > 1e-3  # the parameter moves the orbit: the comparison says something


def test_the_pair_kernel_along_sigma_and_abar_is_the_dedicated_kernel():
    P = get_preset("fig12").params
    x = np.array([0.4, 0.1, 0.8, 0.9, -0.3, 0.2, -0.7, 0.5])
    dedicated = ShootingProblem(P, "sigma", segments=2)
    pair = ShootingProblem(
        P, "sigma", segments=2, sensitivities=("Abar", "sigma")
    )  # reversed: the pair kernel
    np.testing.assert_allclose(
        pair.dparams(x, P.sigma)[:, ::-1], dedicated.dparams(x, P.sigma), rtol=1e-9, atol=1e-11
    )
    np.testing.assert_allclose(
        pair.residual(x, P.sigma), dedicated.residual(x, P.sigma), rtol=1e-9, atol=1e-11
    )
    with pytest.raises(ValueError, match="sensitivities must include the continued parameter"):
        ShootingProblem(P, "sigma", sensitivities=("beta", "eps"))
    with pytest.raises(ValueError, match="'n' is an integer; sensitivities take two of"):
        ShootingProblem(P, "beta", sensitivities=("beta", "n"))


def test_shooting_arcs_are_cached_on_every_parameter():
    # A caller that changes a parameter other than the continued one must not get stale arcs.
    P = get_preset("fig12").params
    x = np.array([0.4, 0.1, 0.8, 0.9])
    problem = ShootingProblem(P, "sigma")
    first = problem.arcs(x, P).ends
    other = problem.arcs(x, P.replace(beta=P.beta + 0.1)).ends
    assert np.max(np.abs(first - other)) > 1e-4
    assert problem.arcs(x, P).ends is first or np.array_equal(problem.arcs(x, P).ends, first)


def test_single_and_multiple_shooting_find_the_same_orbit():
    P = get_preset("fig10").params
    guess = np.array([-2.29697839, 0.4870925, 0.62950163, -1.6026986])
    single = periodic_orbit(P, guess)
    multi = periodic_orbit(P, guess, segments=4)
    assert single.converged and multi.converged
    np.testing.assert_allclose(multi.y0, single.y0, atol=1e-8)
    np.testing.assert_allclose(
        np.sort(np.abs(multi.multipliers)), np.sort(np.abs(single.multipliers)), rtol=1e-6
    )


def test_stable_orbit_attracts_a_long_simulation(scipy_multipliers):
    """Far below resonance (fig10 set, sigma = -6) shooting finds a stable symmetric orbit
    (multipliers 0.945, 0.722), and a simulation from the preset's kicked start settles onto it:
    the strobe state after 300 periods is the orbit's to 1e-6, and it still moves by ~1e-7."""
    P = get_preset("fig10").params.replace(sigma=-6.0)
    strobes = integrator.integrate_grid(P, get_preset("fig10").state0, 2 * np.pi * np.arange(301))
    orbit = periodic_orbit(P, strobes[-100])  # shooting starts 100 periods earlier
    assert orbit.converged and orbit.stable
    np.testing.assert_allclose(
        np.sort(np.abs(orbit.multipliers)), np.sort(np.abs(scipy_multipliers(P, orbit.y0))), rtol=1e-6
    )
    np.testing.assert_allclose(strobes[-1], orbit.y0, atol=1e-6)
    assert orbit_measures(ShootingProblem(P), orbit.y0, -6.0)["symmetry_defect"] < 1e-7  # symmetric


def test_located_fold_and_ns_converge_as_the_tolerance_tightens(scipy_multipliers):
    """fig10 set: a simulation at sigma = 0.8 settles on a stable symmetric orbit; continued
    upwards it loses stability at a Neimark-Sacker point (sigma ~ 0.8806) and turns at a fold
    (~ 0.9242). Located at rtol = 1e-8 and 1e-10, both agree to far better than their distance."""
    P = get_preset("fig10").params.replace(sigma=0.8)
    strobes = integrator.integrate_grid(P, get_preset("fig10").state0, 2 * np.pi * np.arange(201))
    located = []
    for rtol in (1e-8, 1e-10):
        problem = ShootingProblem(P, segments=4, rtol=rtol, atol=rtol * 1e-2)
        start = orbit_at(problem, problem.initial_states(strobes[-1]), 0.8, tol=1e-9)
        assert start.converged and start.stable
        options = ContinuationOptions(
            step=0.02, step_max=0.05, p_min=0.75, p_max=1.0, tol=1e-8, max_steps=200, direction="forward"
        )
        branch = continuation(problem, problem.initial_states(start.y0), 0.8, param="sigma", options=options)
        located.append({s.kind: s.p for s in branch.special if s.kind in ("LP", "NS")})
        ns = next(s for s in branch.special if s.kind == "NS")
        mu = problem.eigenvalues(ns.x, ns.p)
        assert np.min(np.abs(np.abs(mu[np.abs(mu.imag) > 1e-6]) - 1)) < 1e-9  # a complex pair on the circle
    for kind in ("LP", "NS"):
        assert located[0][kind] == pytest.approx(located[1][kind], abs=1e-5)
    # ... and scipy's monodromy (a second integrator) has the critical multipliers there
    lp, ns = (next(s for s in branch.special if s.kind == kind) for kind in ("LP", "NS"))
    assert np.min(np.abs(scipy_multipliers(P.replace(sigma=float(lp.p)), lp.x[:4]) - 1)) < 1e-4
    mu = scipy_multipliers(P.replace(sigma=float(ns.p)), ns.x[:4])
    assert np.min(np.abs(np.abs(mu[np.abs(mu.imag) > 1e-6]) - 1)) < 1e-6


@pytest.mark.parametrize("preset, sigma", [("fig10", -6.0), ("fig13", 2.0)])
def test_orbit_from_the_slow_flow_is_the_orbit_a_simulation_settles_on(preset, sigma):
    # Two independent routes to the same stable orbit: Newton from the leading-order motion of
    # the steady state of (46), and a simulation of (9) from the preset's state until capture.
    from slosh_bif.orbits.starts import orbit_from_slow_flow, settle_and_shoot
    from slosh_bif.slowflow.steady_states import frequency_response

    P = get_preset(preset).params.replace(sigma=sigma)
    (branch,) = frequency_response(P, sigma_min=sigma - 0.1, sigma_max=sigma + 0.1).branches
    orbit = orbit_from_slow_flow(P, float(np.interp(sigma, branch.p, branch.x[:, 0])))
    settled, _ = settle_and_shoot(P, get_preset(preset).state0)
    assert orbit.converged and orbit.stable and settled.stable
    np.testing.assert_allclose(orbit.y0, settled.y0, atol=1e-6)


def test_slow_flow_start_tries_steady_states_and_says_when_none_gives_an_orbit():
    from slosh_bif.continuation import ConvergenceError
    from slosh_bif.orbits.starts import slow_flow_start

    P = get_preset("fig10").params
    start = slow_flow_start(P, -6.0, 8.0)
    assert start.sigma in (-6.0, 8.0) and start.orbit.converged  # the range's ends come first
    # The start carries its own parameter set: Newton there, from its state, stays put.
    again = orbit_at(
        ShootingProblem(start.params, segments=4),
        ShootingProblem(start.params, segments=4).initial_states(start.y0),
        start.sigma,
    )
    assert again.converged and again.iterations <= 1
    # Near the peak (46) and (9) differ by 30 %: no steady state there leads Newton to an orbit.
    with pytest.raises(ConvergenceError, match="no orbit of \\(9\\) found from"):
        slow_flow_start(P, 0.1, 0.3, tries=3)


def test_a_start_from_the_slow_flow_outside_its_checked_range_does_not_warn():
    """A wall losing 70 % of the energy per impact (n = 20, lam 0.35, chi 0.23): the slow flow
    itself warns that it is outside its checked range, but as a start guess for Newton on (9) it is
    no concern (the orbit found does not depend on it), so the start does not warn."""
    import warnings

    from slosh_bif.orbits.starts import slow_flow_start
    from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow

    P = get_preset("fig10").params.replace(
        eps=0.076, beta=0.14, gamma=0.37, Abar=1.17, lam=0.35, chi=0.23, n=20
    )
    with pytest.warns(AsymptoticsWarning, match="outside its checked range"):
        SlowFlow(P)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AsymptoticsWarning)
        start = slow_flow_start(P, 0.5, 3.2)
    assert start.orbit.converged


def test_a_start_for_a_range_without_the_sets_sigma_comes_from_the_slow_flow_inside_it():
    """Fig. 10 at sigma = -6, where the simulation settles: over [2, 8] its orbit could not start
    the family, so the start is the slow flow's, inside the range, a fixed point of scipy's map."""
    from slosh_bif.orbits.starts import start_orbit

    pre = get_preset("fig10")
    start = start_orbit(pre.params.replace(sigma=-6.0), pre.state0, (2.0, 8.0))
    assert 2.0 <= start.params.sigma <= 8.0 and "the set's sigma = -6 lies outside [2, 8]" in start.found_from
    model = SmoothModel(start.params)
    image = period_map(model.rhs, model.jac, start.y0, 2 * np.pi, rtol=1e-12, atol=1e-13)[0]
    np.testing.assert_allclose(image, start.y0, rtol=0, atol=1e-7)


@pytest.mark.parametrize("backend", ["numba", pytest.param("scipy", marks=pytest.mark.slow)])
def test_default_start_does_not_depend_on_rounding_where_the_simulation_has_not_settled(backend):
    """Fig. 10 set at sigma = 1: the 150-period simulation is still strongly modulated, and Newton
    from its strobes lands on whichever orbit the last bits send it to (an asymmetric one after a
    change of summation order in the compiled loop). The default start takes the slow flow's
    instead, on either integrator: the same symmetric orbit of the same sigma (issue 18)."""
    from slosh_bif.orbits.shooting import ShootingProblem
    from slosh_bif.orbits.starts import (
        UnsettledStartError,
        orbit_from_simulation,
        start_orbit,
    )

    pre = get_preset("fig10")
    with pytest.raises(UnsettledStartError, match="has not settled"):
        orbit_from_simulation(pre.params, pre.state0, backend=backend, unsettled="raise")
    start = start_orbit(pre.params, pre.state0, (-6.0, 8.0), backend=backend)
    assert "slow flow" in start.found_from and "not reached a stable orbit" in start.found_from
    problem = ShootingProblem(start.params, segments=4)
    measures = orbit_measures(
        problem, problem.initial_states(start.y0), start.params.sigma, points_per_2pi=64
    )
    assert start.orbit.converged and measures["symmetry_defect"] < 1e-6
    reference = start_orbit(pre.params, pre.state0, (-6.0, 8.0), backend="numba")
    assert start.params.sigma == reference.params.sigma
    np.testing.assert_allclose(start.y0, reference.y0, atol=1e-8)


def test_liouville_check_survives_an_ill_conditioned_monodromy():
    # Four arcs whose product has condition number ~1e16: the determinant of the formed product
    # loses its digits (a period-2 orbit of the Fig. 10 set was flagged at 5.8e-5 that way), the
    # product of the arcs' determinants does not; the check must see accurate arcs as accurate.
    from scipy.stats import special_ortho_group

    P = get_preset("fig10").params
    problem = ShootingProblem(P, segments=4)
    rng = np.random.default_rng(3)
    mats = np.array(
        [
            special_ortho_group.rvs(4, random_state=rng)
            @ np.diag([1e4, 2.0, 0.5, 1e-4])
            @ special_ortho_group.rvs(4, random_state=rng)
            for _ in range(4)
        ]
    )
    dets = [np.linalg.det(m) for m in mats]  # each well conditioned: 1 to rounding
    M = mats[3] @ mats[2] @ mats[1] @ mats[0]
    trace = float(np.log(abs(np.prod(dets))))
    x = np.zeros(16)
    from slosh_bif.orbits.shooting import Arcs

    problem._cache[(x.tobytes(), problem.params_at(P.sigma))] = Arcs(
        np.zeros((4, 4)), mats, np.zeros((4, 4, 2)), trace, M
    )
    assert np.linalg.cond(M) > 1e12
    assert problem.liouville_error(x, P.sigma) < 1e-12 * 16


def test_a_failed_newton_run_integrates_nothing_more():
    # Newton stops where an iterate leaves the domain, without integrating it; the orbit's
    # multipliers and checks are then not computed either (such an iterate deep in the n = 50
    # wall once took minutes of one arc integration in the critical-forcing bench).
    P = get_preset("fig10").params

    class Fenced(ShootingProblem):
        def in_domain(self, x, p):
            return bool(np.array_equal(x, self.start))

    problem = Fenced(P, segments=4)
    problem.start = problem.initial_states(get_preset("fig10").state0)
    orbit = orbit_at(problem, problem.start.copy(), P.sigma)
    assert not orbit.converged and "left the problem's domain" in orbit.message
    assert problem.evaluations == 4  # the start's four arcs, once
    assert np.all(np.isnan(orbit.multipliers)) and not orbit.stable


def test_arcs_from_a_newton_iterate_far_in_the_wall_fail_in_bounded_time():
    # A Newton iterate of the scan (sigma = 1, Fig. 10 set) with w = -3969: the wall term is not
    # finite there, the first step size was NaN, and the compiled loop's step rejection never
    # ended (a scan hung for minutes). Now the arcs fail at once: a NaN residual, which Newton
    # and the corrector read as a failed evaluation.
    P = get_preset("fig10").params.replace(sigma=1.0)
    x = np.array([-218.9, -389.7, -7.0, 618.9, -406.8, 213.8, -3968.6, -2432.7])
    x = np.concatenate([x, [197.8, 388.6, 1619.7, -3720.3, 380.4, -206.7, 788.8, -308.6]])
    problem = ShootingProblem(P, segments=4)
    assert np.all(np.isnan(problem.residual(x, 1.0)))
    run = integrator.integrate(P, x[4:8], (0.0, np.pi / 2))
    assert not run.success and run.steps == 0


@pytest.mark.parametrize("segments", [1, 2, 3, 4])
def test_the_shooting_matrix_is_block_cyclic_with_the_closing_factor(segments):
    """``jacobian_of``: Phi_k on the diagonal, -I to its right, ``-wrap I`` in the block that closes
    the period (with one arc, Phi - wrap I), for the residual's own closing (+1, or -1 on the
    half-period map) and the PD, NS and torus factors; built here block by block from that rule."""
    from slosh_bif.orbits.shooting import Arcs

    rng = np.random.default_rng(segments)
    mats = rng.normal(size=(segments, 4, 4))
    arcs = Arcs(np.zeros((segments, 4)), mats, np.zeros((segments, 4, 2)), 0.0, mats[0])
    for symmetric in (False, True):
        problem = ShootingProblem(get_preset("fig10").params, segments=segments, symmetric=symmetric)
        for wrap in (None, 0.0, 1.0, -1.0, np.exp(0.3j)):
            factor = problem.closing if wrap is None else wrap
            expected = np.zeros(
                (4 * segments, 4 * segments), dtype=complex if np.iscomplexobj(factor) else float
            )
            for k in range(segments):
                expected[4 * k : 4 * k + 4, 4 * k : 4 * k + 4] += mats[k]
                after = (k + 1) % segments
                expected[4 * k : 4 * k + 4, 4 * after : 4 * after + 4] -= (
                    factor if after == 0 else 1.0
                ) * np.eye(4)
            J = problem.jacobian_of(arcs, wrap)
            assert J.dtype == expected.dtype
            np.testing.assert_array_equal(J, expected)


@pytest.mark.parametrize("backend", ["numba", "scipy"])
@pytest.mark.parametrize("pair", [("sigma", "Abar"), ("beta", "lam")])
def test_the_arcs_derivatives_along_a_direction_match_central_differences(backend, pair):
    # The second-order variational equations (two arcs, the Fig. 10 wall n = 50; replayed on the
    # kept steps on the compiled path, integrated with the arcs on scipy's) against central
    # differences of the plain arcs at tighter tolerances; the arcs are the plain ones (to rounding:
    # (sigma, Abar) has a dedicated kernel of its own, written otherwise).
    P = get_preset("fig10").params
    x = np.array([0.4, 0.1, 0.8, 0.9, -0.3, 0.2, -0.7, 0.5])
    d = np.array([0.3, -0.2, 0.5, 0.1, 0.2, 0.4, -0.1, 0.3])

    def problem(rtol):
        return ShootingProblem(
            P, pair[0], segments=2, rtol=rtol, atol=rtol / 100, backend=backend, sensitivities=pair
        )

    along = problem(1e-12)
    arcs, Psi, R = along.arcs_along(x, P, d)
    assert along.arcs(x, P) is arcs  # cached: the residual and Jacobian are these arcs'
    plain = problem(1e-12).arcs(x, P)
    for got, want in ((arcs.ends, plain.ends), (arcs.mats, plain.mats), (arcs.sens, plain.sens)):
        np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-12)
    h, fine = 1e-5, problem(1e-13)
    ahead, behind = fine.arcs(x + h * d, P), fine.arcs(x - h * d, P)
    np.testing.assert_allclose(Psi, (ahead.mats - behind.mats) / (2 * h), rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(R, (ahead.sens - behind.sens) / (2 * h), rtol=1e-5, atol=1e-6)
    assert np.max(np.abs(Psi)) > 1e-2 and np.max(np.abs(R)) > 1e-3  # the comparison says something


def test_derivatives_replayed_on_kept_steps_are_those_of_one_integration_of_all_57():
    # The replay on the tape against the compiled along kernel integrating all 57 components at
    # once with the error norm of the first 29: the same steps but for the two kernels' rounding,
    # which moves them by a little (so the ends agree to the integration's error, not to rounding);
    # and the kept steps grow past a first guess too small for them.
    from slosh_bif.flows.smooth.arcs import Tape, integrate_arcs, replay_along

    P = get_preset("fig10").params
    starts = np.array([[0.4, 0.1, 0.8, 0.9], [-0.3, 0.2, -0.7, 0.5]])
    d = np.array([[0.3, -0.2, 0.5, 0.1], [0.2, 0.4, -0.1, 0.3]])
    taus = np.array([0.0, np.pi, 2 * np.pi])
    tape = Tape(rows_per_arc=4)
    ends, done = integrate_arcs(P, starts, taus, sensitivities=("beta", "lam"), tape=tape)
    assert done == 2 and tape.counts.min() > 4 and tape.rows.shape[1] >= tape.counts.max()
    whole, _ = integrate_arcs(P, starts, taus, sensitivities=("beta", "lam"), directions=d)
    np.testing.assert_allclose(ends, whole[:, :29], rtol=1e-10, atol=1e-12)  # two kernels' rounding
    np.testing.assert_allclose(replay_along(tape, d), whole[:, 29:], rtol=1e-7, atol=1e-9)


@pytest.mark.filterwarnings("ignore:the 150-period simulation")
def test_a_start_orbit_clear_of_the_walls_at_beta_zero_is_reported_as_not_isolated():
    """At beta = 0 the particle is held only by the wall force chi w^(2n+1); an orbit with
    max |w| = 0.07 has a multiplier 2e-5 from +1, so Newton at fixed sigma cannot settle the step
    along it though |F| is at rounding. The error says so and where to start instead. The run has not settled,
    so which such orbit Newton lands on depends on rounding; every one of them is this close to +1."""
    from slosh_bif.continuation import ConvergenceError
    from slosh_bif.model.params import Params
    from slosh_bif.orbits import NO_SWITCHING, orbit_from_simulation, trace_orbits
    from slosh_bif.orbits.settings import ParameterRange

    params = Params(eps=0.12, beta=0.0, gamma=0.15, sigma=4.6, Abar=0.22, lam=0.1, chi=1.0, n=4, pbar=-2)
    start = orbit_from_simulation(params, get_preset("fig10").state_for(params), settle=150)
    assert min(abs(start.orbit.multipliers - 1)) < 1e-4
    with pytest.raises(ConvergenceError, match=r"multiplier at \+1 .* clear of the walls, max \|w\| = 0\.0"):
        trace_orbits(params, start.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=4.0, hi=5.0))
