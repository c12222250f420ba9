"""The compiled exact flow of (8) against independent evaluations: scipy's DOP853 with event location,
the expm event loop, a grazing excursion located by scipy, and the stops it must make."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from slosh_bif import ImpactModel, get_preset, simulate_impact
from slosh_bif.flows.impact.crossings import STICK_RISE
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")


def _at_wall(side):
    def event(t, y):
        return side * y[2] - 1.0

    event.terminal, event.direction = True, 1
    return event


def _next_impact(model, t, y, horizon):
    """The next impact after (t, y) by scipy's DOP853 with event location at tight tolerances."""
    sol = solve_ivp(
        model.rhs,
        (t, t + horizon),
        y,
        method="DOP853",
        rtol=1e-13,
        atol=1e-14,
        events=[_at_wall(1), _at_wall(-1)],
    )
    hits = [(te[0], k) for k, te in enumerate(sol.t_events) if len(te)]
    t_hit, k = min(hits)
    return t_hit, (1, -1)[k], sol.y_events[k][0]


@pytest.mark.parametrize(
    "preset, changes",
    [
        ("fig9a", {}),
        ("fig10", {}),
        ("fig13", {}),
        ("fig10", {"n": 20, "pbar": 2, "lam": 0.2}),
        ("fig13", {"n": 8, "pbar": -2, "lam": 0.05}),
    ],
    ids=["fig9a", "fig10", "fig13", "pbar=2", "pbar=-2"],
)
def test_every_impact_matches_scipy_event_location(preset, changes):
    """Each impact re-found by scipy from the flow's own previous post-impact state: times to 1e-10."""
    p = get_preset(preset)
    params = p.params.replace(**changes)
    model = ImpactModel(params)
    run = simulate_impact(params, p.state0, (0.0, 40.0))
    assert run.success and run.impact_t.size > 10
    after = run.y[:, np.searchsorted(run.t, run.impact_t)]  # the run's own post-impact states
    t, y = 0.0, np.asarray(p.state0, dtype=float)
    for k in range(run.impact_t.size):
        t_hit, side, y_hit = _next_impact(model, t, y, run.impact_t[k] - t + 1.0)
        assert t_hit == pytest.approx(run.impact_t[k], abs=1e-10)
        assert side == run.impact_side[k]
        assert y_hit[3] == pytest.approx(run.impact_v_minus[k], abs=1e-9)
        assert model.impact(y_hit)[3] == pytest.approx(run.impact_v_plus[k], abs=1e-9)
        t, y = run.impact_t[k], after[:, k]


def test_the_compiled_flow_and_the_expm_loop_agree_over_100_periods_of_a_periodic_orbit():
    """Fig. 10 at sigma = 3 settles on a periodic orbit; from there both backends run 100 periods."""
    p = get_preset("fig10")
    params = p.params.replace(sigma=3.0)
    settled = simulate_impact(params, p.state0, (0.0, 400 * np.pi))
    start = settled.y[:, -1]
    t0 = settled.t[-1]
    runs = [simulate_impact(params, start, (t0, t0 + 200 * np.pi), backend=b) for b in ("numba", "scipy")]
    assert all(r.success for r in runs)
    assert runs[0].impact_t.size == runs[1].impact_t.size > 100
    np.testing.assert_allclose(runs[0].impact_t, runs[1].impact_t, rtol=0, atol=1e-10)
    np.testing.assert_allclose(runs[0].y[:, -1], runs[1].y[:, -1], rtol=0, atol=1e-8)
    # and it is periodic: the strobe after 98 and 100 periods agree
    strobe = simulate_impact(params, start, (t0, t0 + 196 * np.pi)).y[:, -1]
    np.testing.assert_allclose(strobe, runs[0].y[:, -1], atol=1e-6)


def _turning_point(model, v):
    """w where the flight from w = 0.97, w' = v at tau = pi (the forcing pulls w back) turns, by scipy."""

    def turn(t, y):
        return y[3]

    turn.terminal, turn.direction = True, -1
    sol = solve_ivp(
        model.rhs,
        (np.pi, np.pi + 6.0),
        [0.0, 0.0, 0.97, v],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14,
        events=turn,
    )
    return sol.y_events[0][0][2]


def test_a_grazing_excursion_is_found_at_any_sample_step():
    """A flight whose turning point lies 1e-9 beyond the wall hits it; one 1e-9 short does not,
    at the coarsest sample step (no sample lies beyond the wall)."""
    params = get_preset("fig10").params
    model = ImpactModel(params)
    for offset, hits in ((1e-9, 1), (-1e-9, 0)):
        v = brentq(lambda v: _turning_point(model, v) - 1.0 - offset, 0.06, 0.14, xtol=1e-16)
        run = simulate_impact(params, [0.0, 0.0, 0.97, v], (np.pi, np.pi + 2.0), sample_step=0.5)
        assert run.success
        assert run.impact_t.size == hits
        assert np.abs(run.y[2]).max() <= 1.0


def test_chattering_stops_as_sticking_in_bounded_impacts():
    """A particle pressed on a wall by the forcing with a lossy Newtonian wall: the impacts
    accumulate at a point in time; the run says so after a bounded number of them."""
    params = get_preset("fig10").params.replace(lam=0.6)
    run = simulate_impact(params, [0.0, 0.0, 1.0 - 1e-6, 1e-3], (0.0, 50.0))
    assert run.status == "sticking" and "sticks" in run.message
    assert 2 < run.impact_t.size < 200
    assert _rise(params, run.impact_t[-1], run.y[:, -1]) < STICK_RISE


def _rise(params, tau, y):
    """How far the flight from the wall-bound state y at tau rises before the push brings it back."""
    w_dd = ImpactModel(params).augmented()[3] @ np.r_[y, np.cos(tau), np.sin(tau)]
    return y[3] ** 2 / (2 * np.sign(y[2]) * w_dd)


def test_a_chatter_below_rounding_sticks_on_both_paths():
    """A random set (n = 35, pbar = 1: kappa -> 1 at vanishing speed) whose particle chatters on
    a wall at tau = 2.386. Its flights shrink below what w's rounding at |w| = 1 resolves: the
    compiled flow at sample step 0.02 once settled there into a spurious chatter at a fixed speed
    of 2e-8 (a million impacts, status max-impacts). Both paths stop at the same impact as sticking."""
    params = get_preset("fig10").params.replace(
        eps=0.0371, beta=0.074, gamma=0.437, sigma=4.758, Abar=3.441, lam=0.589, chi=0.137, n=35, pbar=1
    )
    y0 = [-0.035987, 3.0, 0.97, 3.0]
    runs = [
        simulate_impact(params, y0, (0.0, 3.0), sample_step=0.02, max_impacts=2000, backend=backend)
        for backend in ("numba", "scipy")
    ]
    for run in runs:
        assert run.status == "sticking", run.message
        assert run.impact_t.size < 100
        assert _rise(params, run.impact_t[-1], run.y[:, -1]) < STICK_RISE
    assert runs[0].impact_t.size == runs[1].impact_t.size
    assert abs(runs[0].impact_t[-1] - runs[1].impact_t[-1]) < 1e-9


def test_a_kappa_that_is_not_real_stops_the_run():
    """pbar < 0: eq. (21) loses more than the kinetic energy at small impact speeds (here below
    about 4e-4: delta(1) = 0.21, delta ~ v**(-2/9)); a slow first impact ends the run there."""
    params = get_preset("fig13").params.replace(n=8, pbar=-2, lam=0.1)
    model = ImpactModel(params)
    run = simulate_impact(params, [0.0, 0.0, 1.0 - 1e-10, 1e-4], (0.0, 20.0))
    assert run.status == "kappa-not-real" and "not real" in run.message
    assert run.impact_t.size == 0 and run.t[-1] < 1e-3
    with pytest.raises(ValueError, match="not real"):
        model.kappa(abs(float(run.message.split("speed ")[-1])))


def test_a_start_at_rest_on_a_wall_leaves_it_when_pulled_off_and_sticks_when_pressed():
    """The basins' default plane has rows on the walls (w = +-1, w' = 0). A random set (seed 300):
    at X = -3 the particle on the wall w = -1 is pulled off it (w'' = 2.65 > 0) and flies; on
    w = +1 it is pressed into it and sticks. The compiled flow called the first sticking too (an
    impact at 2e-16 moving off the wall); the expm loop crashed on the second (brentq's bracket)."""
    params = get_preset("fig10").params.replace(
        eps=0.0604, beta=0.19, gamma=0.163, sigma=3.026, Abar=3.376, lam=0.313, chi=1.421, n=3, pbar=3
    )
    w_dd = ImpactModel(params).augmented()[3] @ np.array([-3.0, 0.0, 0.0, 0.0, 1.0, 0.0])
    assert w_dd > 0  # the forcing and the vessel's displacement push w up at both walls alike
    pulled, pressed = (
        [simulate_impact(params, [-3.0, 0.0, w, 0.0], (0.0, 10.0), backend=b) for b in ("numba", "scipy")]
        for w in (-1.0, 1.0)
    )
    assert all(run.success for run in pulled) and pulled[0].impact_t.size == pulled[1].impact_t.size > 0
    assert pulled[0].impact_t[0] > 1.0 and np.allclose(pulled[0].impact_t, pulled[1].impact_t, atol=1e-9)
    for run in pressed:
        assert run.status == "sticking" and run.impact_t.size == 1 and run.impact_t[0] < 1e-12
