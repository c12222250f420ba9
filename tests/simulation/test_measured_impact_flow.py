"""The corrected impact model ((9) without its wall between impacts, and the wall's own
kappa_wall(v) at its clearance |w| = D(v)) on the compiled flow against independent evaluations:
scipy's DOP853 on (9)'s linear part written out here, with the state-dependent wall as its event
function and the law evaluated by numpy; finite differences of the map; an orbit that scipy's map
returns to itself; and the limit of a stiff wall, where (9)'s orbit must approach it."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from slosh_bif import get_preset, simulate_impact
from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.model.restitution.corrected import measured_wall
from slosh_bif.orbits.impact.branches import settled_orbit
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")


def _flight(params):
    """(9) with lam = chi = 0, from its coefficients: a = 1 - eps sigma, b = eps (1 - beta^2) r,
    c = (1 - beta^2) r, d = (eps + beta^2) r with r = (1 - eps sigma) / (1 + eps beta^2)."""
    eps, beta, gamma, sigma, Abar = params.eps, params.beta, params.gamma, params.sigma, params.Abar
    r = (1 - eps * sigma) / (1 + eps * beta**2)
    a, b, c, d = 1 - eps * sigma, eps * (1 - beta**2) * r, (1 - beta**2) * r, (eps + beta**2) * r

    def rhs(tau, y):
        X, Xd, w, wd = y
        common = eps * Abar * np.cos(tau) - eps * gamma * Xd - eps**2 * gamma * wd
        return [Xd, common - a * X - b * w, wd, common - c * X - d * w]

    return rhs


def _reference(params, y0, t0, t1):
    """The state at t1 and the impacts (t, w'-) by scipy: the wall side * w = D(side * w') as the
    event (speeds clamped to the law's range), kappa_wall(v) applied at each."""
    rhs = _flight(params)
    wall = measured_wall(params.lam, params.chi, params.n, params.pbar)

    def clamp(v):
        return min(max(v, wall.v_min), wall.v_max)

    def at_wall(side):
        def event(_t, y):
            return side * y[2] - float(wall.clearance(clamp(side * y[3])))

        event.terminal, event.direction = True, 1
        return event

    t, y, hits = t0, np.array(y0, dtype=float), []
    while True:
        sol = solve_ivp(
            rhs, (t, t1), y, method="DOP853", rtol=1e-13, atol=1e-15, events=(at_wall(1), at_wall(-1))
        )
        if sol.status == 0:
            return sol.y[:, -1], np.array(hits).reshape(-1, 2)
        k = 0 if len(sol.t_events[0]) else 1
        t, y = sol.t_events[k][0], sol.y_events[k][0].copy()
        hits.append((t, y[3]))
        y[3] *= -float(wall.kappa(clamp(abs(y[3]))))


@pytest.mark.parametrize(
    "preset, changes, periods",
    [("fig13", {"sigma": 1.0}, 6), ("fig10", {"sigma": 3.0}, 3), ("fig10", {"sigma": 3.0, "pbar": 2}, 3)],
)
def test_every_impact_matches_scipy_with_the_state_dependent_wall(preset, changes, periods):
    params = get_preset(preset).params.replace(**changes)
    y0, t1 = [0.0, 0.0, 0.0, 0.5], 2 * np.pi * periods
    y_ref, hits_ref = _reference(params, y0, 0.0, t1)
    run = simulate_impact(params, y0, (0.0, t1), variant="corrected")
    assert run.status == "finished" and len(run.impact_t) == len(hits_ref) >= 2
    np.testing.assert_allclose(run.impact_t, hits_ref[:, 0], rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.impact_v_minus, hits_ref[:, 1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.y[:, -1], y_ref, rtol=0, atol=1e-9)
    # the wall is where the law puts it: each impact at |w| = D(|w'-|), off the rigid wall |w| = 1
    wall = measured_wall(params.lam, params.chi, params.n, params.pbar)
    at = np.searchsorted(run.t, run.impact_t)
    speeds = np.clip(np.abs(run.impact_v_minus), wall.v_min, wall.v_max)
    np.testing.assert_allclose(np.abs(run.y[2, at]), wall.clearance(speeds), atol=1e-12)
    assert np.abs(np.abs(run.y[2, at]) - 1.0).max() > 1e-3


@pytest.mark.parametrize("param", ["sigma", "eps", "beta"])
def test_the_map_derivatives_with_the_measured_wall_match_finite_differences(param):
    params = get_preset("fig10").params.replace(sigma=3.0, beta=0.2)
    flow = ImpactFlow(params, param=param, variant="corrected")
    x = flow.run(np.array([0.0, 0.0, 0.0, 0.5]), 0.0, 40 * np.pi, stick_speed=1e-9, max_impacts=10**5)[1][
        :, -1
    ]
    y, phi, dp, impacts, code = flow.strobe(x, 0.0, 2 * np.pi)
    assert code == 0 and len(impacts) >= 2
    h = 1e-6
    fd = np.column_stack(
        [
            (flow.strobe(x + h * e, 0, 2 * np.pi)[0] - flow.strobe(x - h * e, 0, 2 * np.pi)[0]) / (2 * h)
            for e in np.eye(4)
        ]
    )
    np.testing.assert_allclose(phi, fd, atol=1e-7 * np.abs(phi).max())
    value = getattr(params, param)
    moved = [
        ImpactFlow(params.replace(**{param: value + s}), variant="corrected").strobe(x, 0, 2 * np.pi)[0]
        for s in (h, -h)
    ]
    np.testing.assert_allclose(dp, (moved[0] - moved[1]) / (2 * h), atol=1e-7 * max(1.0, np.abs(dp).max()))


def test_an_orbit_of_the_corrected_impact_model_is_a_fixed_point_of_scipys_map():
    params = get_preset("fig10").params.replace(sigma=3.0)
    x = settled_orbit(params, [0.0, 0.0, 0.0, 0.5], periods=60, variant="corrected")
    y, _ = _reference(params, x, 0.0, 2 * np.pi)
    np.testing.assert_allclose(y, x, atol=1e-8)
    # and it is not (8)'s orbit with (21): the two walls differ by several percent at n = 50
    rigid = settled_orbit(params, [0.0, 0.0, 0.0, 0.5], periods=60)
    assert np.abs(rigid - x).max() > 1e-2
    problem = ImpactOrbitProblem(params, variant="corrected")
    assert problem.is_stable(problem.eigenvalues(x, 3.0))


def test_bad_input_for_the_measured_law_is_refused_before_any_work():
    params = get_preset("fig10").params
    with pytest.raises(ValueError, match="variant must be one of"):
        simulate_impact(params, [0, 0, 0, 0.5], (0, 1), variant="rigid")
    with pytest.raises(ValueError, match="inside the measured wall"):
        simulate_impact(params, [0, 0, 1.5, 0.5], (0, 1), variant="corrected")
    with pytest.raises(ValueError, match="param must be one of"):
        ImpactFlow(params, param="lam", variant="corrected")
    with pytest.raises(ValueError, match="no saltation matrices"):
        ImpactFlow(params, exact_flights=True).strobe(np.array([0, 0, 0, 0.5]), 0.0, np.pi)
    with pytest.raises(ValueError, match="compiled flow only"):
        simulate_impact(params, [0, 0, 0, 0.5], (0, 1), variant="corrected", backend="scipy")


def test_a_long_run_in_pieces_goes_on_from_a_piece_ending_in_the_contact_band():
    """`simulate --model impact-corrected` runs (the corrected model) in pieces of 200 time units.
    At a random set (seed 303, n = 6) the first piece ends in the contact band at w = 1.013, beyond
    D(v) at its speed there: the next piece refused that state as a start outside the wall (exit 2).
    The pieces now join into the run in one piece."""
    from slosh_bif.simulation.direct import SimulationSettings, simulate

    preset = get_preset("fig10")
    params = preset.params.replace(
        eps=0.0475, beta=0.404, gamma=0.173, sigma=3.526, Abar=0.698, lam=0.29, chi=1.694, n=6, pbar=0
    )
    y0 = preset.state_for(params)
    pieces = simulate(params, y0, 600.0, settings=SimulationSettings(model="impact-corrected"))
    whole = simulate_impact(params, y0, (0.0, 600.0), sample_step=0.02, variant="corrected")
    assert pieces.success and whole.success and pieces.t.shape == whole.t.shape
    assert np.abs(pieces.y - whole.y).max() < 1e-9
    with pytest.raises(ValueError, match="inside the measured wall"):  # a start given by the user
        simulate_impact(
            params, pieces.y[:, np.searchsorted(pieces.t, 200.0)], (0.0, 1.0), variant="corrected"
        )
