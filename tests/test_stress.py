"""Methods under stress: each case drives a method into a known failure zone and checks that it
fails cleanly (a specific exception, or a result flagged with the reason, in bounded time) or
degrades in a documented way, and never hangs or returns silently wrong numbers.

Every case says what it expects and why. The default run has the fast cases; ``pytest -m slow
tests/test_stress.py`` adds the exhaustive ones.
"""

import warnings
from concurrent.futures import ThreadPoolExecutor
from concurrent.futures import TimeoutError as FutureTimeout

import numpy as np
import pytest

from slosh_bif import Params, SmoothModel, get_preset, simulate_impact
from slosh_bif.continuation import ContinuationOptions, continuation
from slosh_bif.flows.noise import band_limited_noise
from slosh_bif.flows.smooth import integrator
from slosh_bif.model.restitution import kappa, kappa_on_manifold
from slosh_bif.orbits.orbit_tools import periodic_orbit
from slosh_bif.simulation.direct import simulate
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow
from slosh_bif.slowflow.steady_states import frequency_response

HANG_GUARD = 120.0  # seconds: not a speed test, a guard against hanging (each case takes < 2 s here)


def bounded(fn, *args, **kwargs):
    """Run fn in a worker thread and fail the test if it does not return within HANG_GUARD."""
    pool = ThreadPoolExecutor(1)
    future = pool.submit(fn, *args, **kwargs)
    try:
        return future.result(timeout=HANG_GUARD)
    except FutureTimeout:
        pytest.fail(f"{fn.__name__} did not return within {HANG_GUARD} s")
    finally:
        pool.shutdown(wait=False)


def wall_params(n, **changes):
    base = dict(eps=0.05, beta=0.0, gamma=0.0, sigma=0.0, Abar=0.0, lam=0.0, chi=0.2, n=n, pbar=0)
    return Params(**{**base, **changes})


# --- explicit integration on the stiff wall -------------------------------------------------


@pytest.mark.parametrize("n, speed", [(50, 30.0), (200, 30.0), (200, 1e3)])
def test_explicit_integrator_through_a_hard_fast_impact_stays_accurate(n, speed):
    """Expect: DOP853 shrinks its steps in the wall (cost grows with n and speed) but the answer
    stays right. Checked by energy: without damping, forcing and wall dissipation (9) conserves
    it, so the relative energy error after the impact must stay at the tolerance level."""
    P = wall_params(n)
    y0 = np.array([0.0, 0.0, 0.99, speed])
    # Long enough for many wall-to-wall bounces at every speed of the grid.
    run = bounded(integrator.integrate, P, y0, (0.0, 20.0 / speed), rtol=1e-10, atol=1e-12)
    assert run.success, run.message
    model = SmoothModel(P)
    assert abs(model.energy(run.z) - model.energy(y0)) / model.energy(y0) < 1e-7


def test_explicit_integrator_out_of_steps_says_so():
    """Expect: with a step budget too small for the stiff wall, a flagged result
    ('step limit reached'), not a silently truncated state."""
    run = bounded(integrator.integrate, wall_params(200), [0.0, 0.0, 0.99, 1e3], (0.0, 1.0), max_steps=200)
    assert not run.success and run.message == "step limit reached" and run.steps == 200


@pytest.mark.parametrize("backend", ["numba", "scipy"])
def test_state_deep_inside_the_wall_overflows_cleanly(backend):
    """Expect: w = 3 at n = 500 makes chi w^1001 overflow; the integrator reports that it could
    not take a step instead of returning inf or NaN as a state."""
    run = bounded(integrator.integrate, wall_params(500), [0.0, 0.0, 3.0, 0.0], (0.0, 1.0), backend=backend)
    assert not run.success
    assert "step" in run.message.lower() or "spacing" in run.message.lower()
    assert np.all(np.isfinite(run.z))  # the last good state, not garbage


# --- Newton at folds and continuation into the manifold's end ------------------------------


class CubicFold:
    """F(x, p) = x^3 - 3x - p: folds at (x, p) = (1, -2) and (-1, 2), where F_x = 0."""

    names = ("x",)

    def residual(self, x, p):
        return np.array([x[0] ** 3 - 3 * x[0] - p])

    def jacobian(self, x, p):
        return np.array([[3 * x[0] ** 2 - 3.0]])

    def dparam(self, x, p):
        return np.array([-1.0])


def test_continuation_started_exactly_at_a_fold_goes_around_it():
    """Expect: natural-parameter Newton is singular at a fold (F_x = 0); the bordered
    pseudo-arclength corrector is not, so a start exactly at the fold converges and the branch
    goes around it, with the fold located to the engine's tolerance."""
    options = ContinuationOptions(step=0.05, p_min=-2.5, p_max=2.5, max_steps=400, tol=1e-12)
    branch = bounded(continuation, CubicFold(), np.array([1.0]), -2.0, param="p", options=options)
    folds = [s for s in branch.special if s.kind == "LP"]
    assert any(abs(s.p + 2.0) < 1e-8 and abs(s.x[0] - 1.0) < 1e-4 for s in folds)
    assert any(abs(s.p - 2.0) < 1e-8 and abs(s.x[0] + 1.0) < 1e-4 for s in folds)
    assert np.all(np.abs(branch.x[:, 0] ** 3 - 3 * branch.x[:, 0] - branch.p) < 1e-10)


def test_newton_just_past_a_fold_reports_no_orbit():
    """Expect: just past the fold of the symmetric orbit branch (sigma = 0.9242, Fig. 10 set)
    there is no orbit near the stable one of sigma = 0.8; Newton from it stops within max_iter
    with a reason (measured: 'no convergence in 15 Newton steps' at 0.93, a blown-up integration
    at 0.95) and never calls an unconverged state converged."""
    preset = get_preset("fig10")
    P = preset.params.replace(sigma=0.8)
    strobe = integrator.integrate_grid(P, preset.state0, 2 * np.pi * np.arange(201))[-1]
    start = periodic_orbit(P, strobe, segments=4)
    assert start.converged and start.stable
    for sigma in (0.93, 0.95):
        orbit = bounded(periodic_orbit, preset.params.replace(sigma=sigma), start.y0, segments=4, max_iter=15)
        if orbit.converged:  # an orbit elsewhere is legitimate only if it really is one
            assert orbit.residual < 1e-8 and orbit.liouville_error < 1e-6
        else:
            assert orbit.iterations <= 15 and orbit.message
            assert not orbit.residual < 1e-8  # NaN (blown up) or large


def test_frequency_response_stops_exactly_at_the_manifold_end():
    """Expect: the steady states live on S+ only (A >= A_min); the branch ends on A_min with a
    'manifold end' point instead of crossing onto the unstable branch, where (46) means nothing."""
    preset = get_preset("fig13")
    fr = bounded(frequency_response, preset.params, sigma_min=-15, sigma_max=8)
    flow = SlowFlow(preset.params)
    A = np.concatenate([b.x[:, 0] for b in fr.branches])
    assert A.min() >= flow.A_min * (1 - 1e-12)
    ends = [s for b in fr.branches for s in b.special if s.kind == "END"]
    assert any(abs(s.x[0] - flow.A_min) < 1e-6 * flow.A_min for s in ends)


# --- shooting where no periodic orbit exists ----------------------------------------------


def test_shooting_on_a_strongly_modulated_response_reports_failure():
    """Expect: Fig. 12 has no 2pi-orbit near its (strongly modulated) trajectory; Newton from a
    late state of it fails within max_iter steps and says why, never 'converged'."""
    preset = get_preset("fig12")
    late = simulate(preset.params, preset.state0, 1000.0).y[:, -1]
    orbit = bounded(periodic_orbit, preset.params, late, segments=4, max_iter=12)
    if orbit.converged:  # an orbit elsewhere is legitimate only if it really is one
        assert orbit.residual < 1e-8 and not orbit.stable
    else:
        assert orbit.iterations <= 12 and orbit.message


# --- the asymptotics outside their range ---------------------------------------------------


@pytest.mark.parametrize(
    "changes, concern",
    [(dict(eps=0.3), "eps = 0.3 > 0.1"), (dict(beta=0.95), "beta = 0.95 > 0.5"), (dict(n=6), "eq. \\(21\\)")],
)
def test_slow_flow_outside_its_range_warns(changes, concern):
    """Expect: the slow flow still computes (it is a well-defined ODE) but warns, naming the
    reason, where its error is known or expected to be large."""
    P = get_preset("fig10").params.replace(**changes)
    with pytest.warns(AsymptoticsWarning, match=concern):
        fr = frequency_response(P, sigma_min=-2, sigma_max=2)
    assert all(np.all(np.isfinite(b.x)) for b in fr.branches)


def test_slow_flow_in_range_does_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error", AsymptoticsWarning)
        SlowFlow(get_preset("fig10").params)


# --- restitution where kappa is not real --------------------------------------------------


def test_restitution_not_real_is_an_error_or_a_flagged_stop():
    """Expect: eq. (21) has no real kappa when the first-order dissipation exceeds the kinetic
    energy. As a parameter set: ValueError naming kappa. Inside a run (pbar < 0: dissipation grows
    as impacts slow down): the impact simulation stops with status 'kappa-not-real' and the time."""
    with pytest.raises(ValueError, match="restitution coefficient kappa"):
        Params(eps=0.05, beta=0.0, gamma=0.0, sigma=0.0, Abar=0.0, lam=0.5, chi=0.2, n=6, pbar=-4)
    with pytest.raises(ValueError, match="not real for impact speed"):
        kappa(0.1, 0.3, 0.2, 6, -4)
    P = Params(eps=0.05, beta=0.0, gamma=0.0, sigma=0.0, Abar=0.0, lam=0.3, chi=0.2, n=6, pbar=-4)
    run = bounded(simulate_impact, P, [0.5, 0.5, 0.0, 1.0], (0, 500))
    assert run.status == "kappa-not-real" and "tau =" in run.message
    assert run.t[-1] < 500
    with pytest.raises(ValueError, match="no restitution coefficient"):
        kappa_on_manifold(1e-3, 0.3, 0.2, 6, -4)


# --- non-finite input ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "call",
    [
        lambda: Params(eps=float("nan"), beta=0, gamma=0, sigma=0, Abar=0, lam=0.1, chi=0.2, n=6, pbar=0),
        lambda: get_preset("fig10").params.replace(sigma=float("inf")),
        lambda: simulate(get_preset("fig10").params, [0, 0, np.nan, 0], 10.0),
        lambda: simulate(get_preset("fig10").params, [0, 0, 0, 0], np.inf),
        lambda: integrator.integrate(get_preset("fig10").params, [0, 0, 0, np.inf], (0, 1)),
        lambda: periodic_orbit(get_preset("fig10").params, [np.nan, 0, 0, 0]),
        lambda: band_limited_noise(np.nan, seed=0, duration=10.0),
        lambda: frequency_response(get_preset("fig10").params, sigma_min=-np.inf, sigma_max=1.0),
        lambda: kappa(np.nan, 0.3, 0.2, 6, 0),
    ],
)
def test_non_finite_input_is_rejected_before_any_work(call):
    with pytest.raises(ValueError):
        call()


# --- exhaustive (slow) --------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("n", [10, 50, 100, 200, 400])
@pytest.mark.parametrize("speed", [1.0, 10.0, 100.0, 1000.0])
def test_stiff_wall_grid(n, speed):
    """The energy check of the fast case over a grid of n and impact speed."""
    test_explicit_integrator_through_a_hard_fast_impact_stays_accurate(n, speed)


@pytest.mark.slow
@pytest.mark.parametrize("sigma", [0.5, 1.0, 2.0, 3.0])
def test_shooting_on_strongly_modulated_responses_over_sigma(sigma):
    preset = get_preset("fig12")
    P = preset.params.replace(sigma=sigma)
    late = simulate(P, preset.state0, 1500.0).y[:, -1]
    orbit = bounded(periodic_orbit, P, late, segments=4, max_iter=12)
    assert not orbit.converged or orbit.residual < 1e-8


def test_a_writer_that_fails_leaves_the_previous_file_and_no_partial_one(tmp_path):
    """Outputs are written whole or not at all (issue 18): a CSV writer interrupted mid-way (an
    exception from a row, as a kill or a full disk would) keeps the previous complete file."""
    from slosh_bif.report.tables import write_rows

    path = tmp_path / "table.csv"
    write_rows([{"a": 1.0}], ["a"], path)
    before = path.read_text()

    def rows():
        yield {"a": 2.0}
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_rows(rows(), ["a"], path)
    assert path.read_text() == before
    assert [p.name for p in tmp_path.iterdir()] == ["table.csv"]


def test_a_slow_departure_from_the_wall_is_a_free_flight_in_bounded_time():
    """A particle leaving the wall at 1e-10 with the forcing pulling it off stays within w's rounding
    of the wall for 1e-6 of tau. The flow's certificate tested the wall against w there and halved
    down to 1e-16 of tau (5e9 intervals, about 20 minutes; a random set's grazing crossing met it
    at 1e-8, 7 s a call). The falling slope now certifies the flight free: no impact, and the state
    of expm's flight (scipy) to 1e-12."""
    from scipy.linalg import expm

    from slosh_bif import ImpactModel

    params = get_preset("fig10").params.replace(
        eps=0.0723, beta=0.223, gamma=0.297, sigma=-0.1954, Abar=2.583, lam=0.563, chi=1.082, n=6, pbar=2
    )
    tau, y0 = 3.0706, np.array([-0.5484, -5.1861, -1.0, 1e-10])
    K = ImpactModel(params).augmented()
    assert K[3] @ np.r_[y0, np.cos(tau), np.sin(tau)] > 0.1  # pulled off the wall w = -1
    run = bounded(simulate_impact, params, y0, (tau, tau + 0.5))
    assert run.success and run.impact_t.size == 0
    flight = expm(K * 0.5) @ np.r_[y0, np.cos(tau), np.sin(tau)]
    assert np.abs(run.y[:, -1] - flight[:4]).max() < 1e-12
