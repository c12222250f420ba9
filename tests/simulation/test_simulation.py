"""Direct simulation (8)/(9), the noise of (47) and the regime classifier, against independent values."""

import csv
import dataclasses

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from slosh_bif import ImpactModel, SmoothModel, get_preset, simulate_impact
from slosh_bif.flows.noise import band_limited_noise
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.orbits.orbit_tools import periodic_orbit
from slosh_bif.simulation.direct import Noise, Simulation, SimulationSettings, simulate
from slosh_bif.simulation.regimes import classify
from slosh_bif.simulation.settings import Workers
from slosh_bif.slowflow.critical import critical_forcing
from slosh_bif.slowflow.steady_states import frequency_response


def linear_periodic_response(params, model="impact"):
    """Closed form: the 2pi-periodic solution without impacts, y = Re(Y exp(i tau)), of (8) or of
    the linear part of (9) (the wall terms chi w^(2n+1), lam w^(2p) w' are below 1e-16 at |w| < 0.1)."""
    if model == "impact":
        impact = ImpactModel(params)
        matrix, forcing = impact.matrix, impact.forcing
    else:
        smooth = SmoothModel(params)
        zero = np.zeros(4)
        matrix, forcing = smooth.jac(0.0, zero), smooth.rhs(0.0, zero)
    return np.linalg.solve(1j * np.eye(4) - matrix, forcing)


# --- noise (47) ---------------------------------------------------------------------------


def test_noise_is_the_band_limited_sum_of_cosines_with_the_requested_std():
    noise = band_limited_noise(4.0, seed=3, duration=300.0, cutoff=6.0)
    # Independent evaluation: the defining sum of cosines, from the same phase draw.
    length = 1.05 * 300.0 + 2 * np.pi
    dw = 2 * np.pi / length
    phases = np.random.default_rng(3).uniform(0, 2 * np.pi, noise.modes)
    assert noise.modes == int(6.0 / dw)
    tau = np.random.default_rng(0).uniform(0, 300, 50)
    exact = (
        4.0
        * np.sqrt(2 / noise.modes)
        * np.cos(np.outer(tau, dw * np.arange(1, noise.modes + 1)) + phases).sum(axis=1)
    )
    np.testing.assert_allclose(
        noise(tau), exact, atol=1e-6 * 4.0
    )  # degree-7 spline, 16 points per shortest period
    samples = noise(np.linspace(0, 300, 100_001))
    assert np.std(samples) == pytest.approx(4.0, rel=0.05)
    assert abs(np.mean(samples)) < 0.1 * 4.0
    # Band-limited: no power above the cutoff (Hann window against leakage from the cut ends).
    spectrum = np.abs(np.fft.rfft(samples * np.hanning(samples.size))) ** 2
    omega = 2 * np.pi * np.fft.rfftfreq(samples.size, d=300 / 100_000)
    assert spectrum[omega > 1.2 * 6.0].sum() < 1e-5 * spectrum.sum()


def test_noise_is_reproducible_bit_for_bit_and_seed_dependent():
    a = band_limited_noise(2.0, seed=11, duration=100.0)
    b = band_limited_noise(2.0, seed=11, duration=100.0)
    c = band_limited_noise(2.0, seed=12, duration=100.0)
    assert np.array_equal(a.table, b.table)
    assert not np.array_equal(a.table, c.table)
    P = get_preset("fig15").params
    runs = [simulate(P, get_preset("fig15").state0, 40.0, noise=Noise(std=4.0, seed=5)) for _ in range(2)]
    assert np.array_equal(runs[0].y, runs[1].y)
    assert not np.array_equal(
        runs[0].y, simulate(P, get_preset("fig15").state0, 40.0, noise=Noise(std=4.0, seed=6)).y
    )


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(std=-1.0, seed=0, duration=10.0), "noise std"),
        (dict(std=1.0, seed=0, duration=0.0), "noise duration"),
        (dict(std=1.0, seed=0, duration=10.0, cutoff=np.inf), "noise cutoff"),
        (dict(std=1.0, seed=-2, duration=10.0), "noise seed"),
    ],
)
def test_noise_rejects_bad_input(kwargs, message):
    std = kwargs.pop("std")
    with pytest.raises(ValueError, match=message):
        band_limited_noise(std, **kwargs)


def test_noisy_response_converges_as_the_step_shrinks():
    """The forcing is defined before the solver runs, so tighter tolerances (smaller steps) converge.

    (With the paper's one draw per step the forcing itself would change with every step.)
    """
    preset = get_preset("fig14")
    noise, coarse = Noise(std=4.0, seed=1), SimulationSettings(sample_step=0.05)
    ends = [
        simulate(
            preset.params, preset.state0, 30.0, noise=noise, settings=coarse.replace(rtol=r, atol=r * 1e-2)
        ).y[:, -1]
        for r in (1e-5, 1e-7, 1e-9, 1e-11)
    ]
    diffs = [np.max(np.abs(ends[k + 1] - ends[k])) for k in range(3)]
    assert diffs[0] > diffs[1] > diffs[2]
    assert diffs[2] < 1e-5
    # The scipy fallback integrates the same forcing to the same answer.
    other = simulate(
        preset.params,
        preset.state0,
        30.0,
        noise=noise,
        settings=coarse.replace(rtol=1e-11, atol=1e-13, backend="scipy"),
    ).y[:, -1]
    np.testing.assert_allclose(other, ends[-1], atol=1e-5)
    # And the noise matters: without it the end state is elsewhere.
    quiet = simulate(
        preset.params,
        preset.state0,
        30.0,
        settings=SimulationSettings(rtol=1e-11, atol=1e-13, sample_step=0.05),
    ).y[:, -1]
    assert np.max(np.abs(quiet - ends[-1])) > 1e-2


def test_simulate_rejects_bad_input():
    P = get_preset("fig10").params
    y0 = get_preset("fig10").state0
    with pytest.raises(ValueError, match="model must be one of smooth, impact"):
        simulate(P, y0, 10.0, settings=SimulationSettings(model="rk4"))
    with pytest.raises(ValueError, match="noise needs a seed"):
        simulate(P, y0, 10.0, noise=Noise(std=1.0))
    with pytest.raises(ValueError, match="smooth model only"):
        simulate(P, y0, 10.0, settings=SimulationSettings(model="impact"), noise=Noise(std=1.0, seed=0))
    with pytest.raises(ValueError, match="tmax must be finite"):
        simulate(P, y0, -1.0)
    with pytest.raises(ValueError, match="noise std"):
        simulate(P, y0, 10.0, noise=Noise(std=np.nan, seed=0))


# --- the impact model's events against an independent event search ------------------------


def test_impact_times_and_velocities_match_a_refined_event_search():
    """Re-find every impact with scipy's DOP853 event location from the previous post-impact state."""
    preset = get_preset("fig10")
    P = preset.params
    model = ImpactModel(P)
    traj = simulate_impact(P, preset.state0, (0, 60))
    assert traj.success and traj.impact_t.size > 15

    def at_wall(side):
        def event(_t, y):
            return side * y[2] - 1.0

        event.terminal = True
        event.direction = 1
        return event

    t, y = 0.0, preset.state0.copy()
    for k in range(traj.impact_t.size):
        sol = solve_ivp(
            model.rhs,
            (t, traj.impact_t[k] + 1.0),
            y,
            method="DOP853",
            rtol=1e-12,
            atol=1e-13,
            events=[at_wall(1), at_wall(-1)],
        )
        hits = [(e[0], s) for e, s in zip(sol.t_events, (1, -1)) if e.size]
        t_hit, side = min(hits)
        assert t_hit == pytest.approx(traj.impact_t[k], abs=1e-8)
        assert side == traj.impact_side[k]
        y_hit = sol.y_events[0 if side == 1 else 1][0]
        assert y_hit[3] == pytest.approx(traj.impact_v_minus[k], abs=1e-7)
        y = model.impact(y_hit)
        assert y[3] == pytest.approx(traj.impact_v_plus[k], abs=1e-7)
        # Continue from the reference's own post-impact state so that errors do not accumulate.
        t, y = traj.impact_t[k], np.array([y_hit[0], y_hit[1], float(side), traj.impact_v_plus[k]])


def test_smooth_wall_passages_do_not_depend_on_the_sampling():
    # Up to tau = 45 only: the Fig. 10 response amplifies differences ~16-fold a period, so runs
    # with different output grids (hence different steps) part after ~8 periods.
    preset = get_preset("fig10")
    coarse = simulate(preset.params, preset.state0, 45.0, settings=SimulationSettings(sample_step=0.02))
    fine = simulate(
        preset.params,
        preset.state0,
        45.0,
        settings=SimulationSettings(sample_step=0.004, rtol=1e-11, atol=1e-13),
    )
    assert coarse.impact_t.size == fine.impact_t.size > 15
    np.testing.assert_allclose(coarse.impact_t, fine.impact_t, atol=5e-3)
    np.testing.assert_array_equal(coarse.impact_side, fine.impact_side)


@pytest.mark.parametrize("n", [6, 1000, 5000])
def test_contacts_shorter_than_a_sample_are_found_from_the_state(n):
    """At n = 1000 a contact lasts ~1e-3, a twentieth of the sample step: sampled |w| alone missed
    two thirds of the impacts. Against sampling finer than the contact (2e-5), every impact is
    found, at the same time and with the same speeds, and each reverses w'."""
    preset = get_preset("fig10")
    P = preset.params.replace(n=n)
    coarse = simulate(P, preset.state_for(P), 12.0, settings=SimulationSettings(sample_step=0.02))
    fine = simulate(P, preset.state_for(P), 12.0, settings=SimulationSettings(sample_step=2e-5))
    assert coarse.impact_t.size == fine.impact_t.size >= 7
    np.testing.assert_array_equal(coarse.impact_side, fine.impact_side)
    np.testing.assert_allclose(coarse.impact_t, fine.impact_t, atol=1e-6)
    np.testing.assert_allclose(coarse.impact_v_minus, fine.impact_v_minus, atol=1e-4)
    np.testing.assert_allclose(coarse.impact_v_plus, fine.impact_v_plus, atol=1e-4)
    assert np.all(coarse.impact_v_minus * coarse.impact_v_plus < 0)


# --- the regime classifier on cases whose regime is known independently -------------------


def test_non_resonant_on_the_closed_form_linear_response():
    """Start on the closed-form impact-free periodic response (|w| < 1): it never impacts."""
    P = get_preset("fig11b").params
    for model in ("smooth", "impact"):
        Y = linear_periodic_response(P, model)
        assert np.max(np.abs(Y[2])) < 0.1
        y0 = Y.real  # the state at tau = 0
        summary = classify(simulate(P, y0, 300.0, settings=SimulationSettings(model=model)))
        assert summary.regime == "non-resonant", summary.reason
        assert summary.impacts_per_period == 0
        # The measured envelope is the closed-form amplitude of X (sampled peaks: 1e-3).
        assert summary.envelope_max == pytest.approx(abs(Y[0]), rel=1e-3)
        assert summary.envelope_min == pytest.approx(abs(Y[0]), rel=1e-3)


def test_strongly_modulated_where_neither_steady_state_exists():
    """Fig. 12: the slow flow has no steady state on S+ (Abar < Abar_b) and the impact-free
    periodic response would cross the walls (max |w| > 1): the response must modulate."""
    preset = get_preset("fig12")
    P = preset.params
    assert critical_forcing(P, P.sigma).Abar_b > P.Abar
    assert np.abs(linear_periodic_response(P)[2]) > 1
    summary = classify(simulate(P, preset.state0, 3000.0))
    assert summary.regime == "strongly-modulated", summary.reason
    assert summary.envelope_min < summary.A_min < summary.envelope_max


def test_periodic_resonant_matches_the_slow_flow_steady_state():
    """Fig. 13: a stable steady state of the slow flow exists on S+; the simulation sits on it."""
    preset = get_preset("fig13")
    P = preset.params
    summary = classify(
        simulate(P, preset.state0, 3000.0), transient=2000.0
    )  # capture happens near tau = 1000
    assert summary.regime == "periodic-resonant", summary.reason
    fr = frequency_response(P, sigma_min=P.sigma - 0.01, sigma_max=P.sigma + 0.01)
    stable = [
        b.x[np.argmin(np.abs(b.p - P.sigma)), 0]
        for b in fr.branches
        if b.stable[np.argmin(np.abs(b.p - P.sigma))]
    ]
    assert len(stable) == 1
    # Peak |X| 0.28 against the slow flow's A = 0.31: the asymptotics' accuracy here (beta = 0.3).
    assert summary.envelope_max == pytest.approx(stable[0], rel=0.15)


def test_periodic_resonant_is_a_stable_periodic_orbit_of_the_smooth_model():
    """Fig. 10 set at sigma = 0.8: shooting from the end state converges to a stable 2pi-orbit
    whose peak |X| is the measured envelope."""
    preset = get_preset("fig10")
    P = preset.params.replace(sigma=0.8)
    # Close to the Neimark-Sacker point at sigma = 0.881 the approach is a slowly decaying
    # oscillation of the envelope: judge the last 50 of 300 periods.
    sim = simulate(P, preset.state0, 2 * np.pi * 300, settings=SimulationSettings(sample_step=0.01))
    summary = classify(sim, transient=2 * np.pi * 250)
    assert summary.regime == "periodic-resonant", summary.reason
    orbit = periodic_orbit(P, sim.y[:, -1], segments=4)
    assert orbit.converged and orbit.stable
    taus = np.linspace(0, 2 * np.pi, 2001)
    peak = np.max(np.abs(integrate_grid(P, orbit.y0, taus)[:, 0]))
    assert summary.envelope_max == pytest.approx(peak, rel=1e-2)
    assert summary.envelope_min == pytest.approx(peak, rel=1e-2)
    assert summary.impacts_per_period == pytest.approx(
        4.0, abs=0.05
    )  # two on each wall: see docs/findings/simulation.md


def synthetic(envelope_per_period, sides_per_period, params):
    """A hand-made response: X = A_k sin(tau) in period k, impacts at the given walls."""
    periods = len(envelope_per_period)
    t = np.linspace(0, 2 * np.pi * periods, 200 * periods + 1)
    A = np.repeat(envelope_per_period, 200)
    A = np.append(A, A[-1])
    X = A * np.sin(t)
    y = np.vstack([X, A * np.cos(t), X, A * np.cos(t)])
    impact_t = np.concatenate(
        [2 * np.pi * k + np.linspace(0.5, 5.5, len(sides_per_period)) for k in range(periods)]
    )
    sides = np.tile(sides_per_period, periods)
    zeros = np.zeros_like(impact_t)
    return Simulation("smooth", params, t, y, impact_t, sides, zeros, zeros, "finished", "synthetic")


def test_classifier_rules_on_synthetic_responses():
    P = get_preset("fig13").params
    # A period-2 envelope (alternating amplitudes) with impacts, far above A_min: none of the three.
    summary = classify(synthetic(np.tile([1.0, 0.6], 60), [1, -1], P), transient=0.0)
    assert summary.regime == "other"
    assert summary.crossings_per_period == pytest.approx(2.0, abs=0.05)
    # No impacts at all: non-resonant whatever the envelope.
    quiet = dataclasses.replace(
        synthetic(np.full(60, 0.5), [1, -1], P), impact_t=np.empty(0), impact_side=np.empty(0, int)
    )
    assert classify(quiet, transient=0.0).regime == "non-resonant"
    with pytest.raises(ValueError, match="transient must leave at least two forcing periods"):
        classify(quiet, transient=1e6)


def test_an_envelope_beyond_the_upper_end_of_s_plus_is_classified_not_refused():
    """pbar = 3 (a random draw): S+ ends at A = 3.18 where (39) folds. A steady response of two
    crossings a period at A = 4.6, beyond that end, is judged (not resonant on S+: "other"), as
    (8) gives it at sigma = -0.5, Abar = 3; one below S+ is said to be below it."""
    from slosh_bif.model.restitution.on_manifold import ManifoldLaw

    P = get_preset("fig10").params.replace(
        eps=0.0715, beta=0.2, gamma=0.33, sigma=-0.5, Abar=3.0, lam=0.36, chi=0.88, n=5, pbar=3
    )
    law = ManifoldLaw(P)
    assert 3.0 < law.A_max < 4.0
    summary = classify(synthetic(np.full(60, 4.6), [1, -1], P), transient=0.0)
    assert summary.regime == "other" and f"beyond S+, which ends at A = {law.A_max:.4g}" in summary.reason
    below = classify(synthetic(np.full(60, 0.5 * law.A_min), [1, -1], P), transient=0.0)
    assert "below S+" in below.reason


def test_regime_map_runs_through_any_executor():
    """The map through a user's executor (threads here; a Dask client's executor the same way)
    gives what classifying each point by itself gives."""
    from concurrent.futures import ThreadPoolExecutor

    from slosh_bif.simulation.regimes import regime_map

    preset = get_preset("fig12")
    sigmas, abars = [0.0, 1.0], [0.05, 0.5]
    with ThreadPoolExecutor(2) as pool:
        rmap = regime_map(preset.params, preset.state0, sigmas, abars, tmax=400.0, workers=Workers(pool))
    assert rmap.regime.shape == (2, 2)
    for i, a in enumerate(abars):
        for j, s in enumerate(sigmas):
            alone = classify(simulate(preset.params.replace(sigma=s, Abar=a), preset.state0, 400.0))
            assert rmap.regime[i, j] == alone.regime
            assert rmap.summaries[i][j].envelope_max == alone.envelope_max
    with pytest.raises(ValueError, match="Abar must be >= 0"):
        regime_map(preset.params, preset.state0, sigmas, [-1.0], workers=Workers(pool))


def test_morlet_ridge_reads_the_amplitude_and_frequency_of_a_cosine():
    from slosh_bif.simulation.wavelet import morlet_transform

    dt = 0.1
    t = np.arange(0, 400, dt)
    omegas = np.linspace(0.5, 2.0, 151)
    W = morlet_transform(0.7 * np.cos(1.3 * t) + 0.2 * np.cos(0.6 * t), dt, omegas)
    middle = W[:, t.size // 2]
    assert omegas[np.argmax(middle)] == pytest.approx(1.3, abs=0.011)
    assert middle.max() == pytest.approx(0.7, rel=0.01)
    with pytest.raises(ValueError, match="omegas must lie in"):
        morlet_transform(t, dt, [40.0])


def test_a_failed_run_in_a_regime_map_is_recorded_as_failed_with_its_reason(monkeypatch, tmp_path):
    from concurrent.futures import ThreadPoolExecutor

    from slosh_bif.simulation import regimes
    from slosh_bif.simulation.output import write_regime_csv

    P = get_preset("fig13").params

    def failing(params, state0, tmax, **_):
        t = np.linspace(0, 1, 5)
        return Simulation(
            "smooth",
            params,
            t,
            np.zeros((4, 5)),
            np.empty(0),
            np.empty(0, int),
            np.empty(0),
            np.empty(0),
            "failed",
            "step size fell below the rounding limit",
        )

    monkeypatch.setattr(regimes, "simulate", failing)
    with ThreadPoolExecutor(1) as pool:
        rmap = regimes.regime_map(P, [0.0, 0.0, 0.5, 0.0], [1.0], [1.0], tmax=100.0, workers=Workers(pool))
    assert rmap.regime[0, 0] == "failed"
    assert "simulation failed: step size fell below the rounding limit" in rmap.summaries[0][0].reason
    row = next(csv.DictReader(open(write_regime_csv(rmap, tmp_path / "regimes.csv"))))
    assert row["regime"] == "failed" and "rounding limit" in row["reason"]


def _sources_digest(modules):
    import hashlib

    return hashlib.sha256(b"".join(open(m.__file__, "rb").read() for m in modules)).hexdigest()


def test_cached_machine_code_is_dropped_when_the_sources_it_compiled_in_change(tmp_path):
    # numba keys a cache on the function's own file; the loops inline or call functions of other
    # files (the generated kernels, the impact search), so a change to any of them must remove the
    # caches of every module that compiled them in (a stale one ran the old code).
    import types

    from slosh_bif.flows.compiled import forget_stale_compilations
    from slosh_bif.model import powers
    from slosh_bif.model._generated import kernels

    locator = types.SimpleNamespace(get_cache_path=lambda: str(tmp_path))
    compiled = types.SimpleNamespace(
        _cache=types.SimpleNamespace(_impl=types.SimpleNamespace(locator=locator))
    )
    stale = [
        tmp_path / "dop853._dop853_loop-1.py311.nbi",
        tmp_path / "dop853._dop853_loop-1.py311.1.nbc",
        tmp_path / "tape.replay_loop-1.py311.nbi",
    ]
    other = tmp_path / "noise.other-1.py311.nbi"
    for path in (*stale, other):
        path.write_text("x")
    (tmp_path / "loops.sha256").write_text("the digest of older kernels")
    sources = (kernels, powers)
    forget_stale_compilations(compiled, sources, ("dop853", "tape"), "loops")
    assert not any(p.exists() for p in stale) and other.exists()
    assert (tmp_path / "loops.sha256").read_text() == _sources_digest(sources)
    stale[0].write_text("x")  # compiled from the current sources: kept
    forget_stale_compilations(compiled, sources, ("dop853", "tape"), "loops")
    assert stale[0].exists()


def test_each_compiled_loop_keeps_the_digest_of_every_source_it_compiles_in(tmp_path):
    """The loops of (9) and the exact flow of (8) record, beside their cache, the digest of all the
    files they inline or call: a change to the impact search alone (crossings.py) once left the flow
    running its old code. Imported in a fresh process whose numba cache is an empty folder."""
    import importlib
    import os
    import subprocess
    import sys

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    code = "import slosh_bif.flows.impact.flow, slosh_bif.flows.smooth.dop853"
    subprocess.run([sys.executable, "-c", code], env=env, check=True)
    expected = {
        "dop853.kernels.sha256": (
            "model._generated.kernels",
            "model.powers",
            "flows.smooth.variations",
            "flows.smooth.dop853",
        ),
        "impact.sources.sha256": (
            "flows.impact.crossings",
            "flows.impact.band",
            "model._generated.impact_kernels",
            "flows.impact.flow",
        ),
    }
    for name, modules in expected.items():
        (marker,) = tmp_path.rglob(name)
        sources = [importlib.import_module(f"slosh_bif.{m}") for m in modules]
        assert marker.read_text() == _sources_digest(sources), name


def test_a_run_that_sticks_before_the_judged_window_is_non_resonant():
    """A random set (seed 306: n = 35, pbar = 1) whose particle sticks to a wall at tau = 2.39, long
    before the second half of a 600-unit run: (8) ends there, and the run is non-resonant, as a
    sticking run judged after its transient is. `regimes --model impact` at this set ended with
    "transient must leave at least two forcing periods" (exit 2)."""
    preset = get_preset("fig10")
    params = preset.params.replace(
        eps=0.0371, beta=0.074, gamma=0.437, sigma=4.758, Abar=3.441, lam=0.589, chi=0.137, n=35, pbar=1
    )
    sim = simulate(params, preset.state_for(params), 600.0, settings=SimulationSettings(model="impact"))
    assert sim.status == "sticking" and sim.t[-1] < 3.0
    for transient in (None, 300.0):
        summary = classify(sim, transient=transient)
        assert summary.regime == "non-resonant" and "sticks to a wall" in summary.reason
    with pytest.raises(ValueError, match="transient must leave"):  # a run that ended another way
        classify(dataclasses.replace(sim, status="max-impacts"), transient=300.0)
