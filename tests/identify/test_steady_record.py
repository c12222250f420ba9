"""A settled forced record fitted by the orbits of (9) and (8): the samples' derivatives against
differences of Newton-solved orbits, clean records simulated independently (scipy's DOP853 on
(9), the expm event loop on (8)) given back from parameters far off, a wrong wall power said not
to fit, records at two frequencies fitted together, the command and its refusals."""

import json
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.identify.steady_fit import fit_steady_record
from slosh_bif.identify.steady_record import RecordOrbit, SteadyRecord, read_steady_record
from slosh_bif.model.equations import ImpactModel, SmoothModel
from slosh_bif.simulation.vibro_impact import simulate_impact
from slosh_bif.slowflow.flow import AsymptoticsWarning

SMOOTH = get_preset("fig10").params.replace(eps=0.04, beta=0.1, n=20, lam=0.4, gamma=0.25, sigma=-1.0)
IMPACT = get_preset("fig10").params.replace(
    eps=0.03, beta=0.2, n=30, lam=0.3, gamma=0.25, Abar=2.5, sigma=3.0
)
TAU = np.arange(144) * (2 * np.pi / 48)  # three forcing periods, 48 samples each


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        yield


def _settled_smooth(params):
    """(9) settled from rest by the compiled integrator (600 periods), then sampled by scipy's
    DOP853 at TAU (the fit's integrator is neither)."""
    y = integrate_grid(params, np.zeros(4), np.array([0.0, 600 * 2 * np.pi]), rtol=1e-11, atol=1e-13)[-1]
    run = solve_ivp(SmoothModel(params).rhs, (0.0, TAU[-1]), y, "DOP853", rtol=1e-12, atol=1e-13, t_eval=TAU)
    assert np.abs(run.y[0][:96] - run.y[0][48:]).max() < 1e-8  # a 2pi-orbit (most sigmas here modulate)
    return SteadyRecord(TAU, run.y[0], None, "dop853")


@pytest.fixture(scope="module")
def smooth_record():
    return _settled_smooth(SMOOTH)


@pytest.fixture(scope="module")
def two_records(smooth_record):
    """The record at sigma = -1 and another at sigma = 0.6, in one record with each sample's sigma."""
    other = _settled_smooth(SMOOTH.replace(sigma=0.6))
    return SteadyRecord(
        np.tile(TAU, 2),
        np.concatenate([smooth_record.X, other.X]),
        None,
        "two",
        np.repeat([-1.0, 0.6], len(TAU)),
    )


def _settled_impact(params):
    """(8) settled from rest by the compiled flow (600 periods), then three periods by the expm event
    loop (scipy backend), X at TAU by the flight's expm from the loop's last sample before each."""
    t0 = 600 * 2 * np.pi
    y = simulate_impact(params, np.zeros(4), (0.0, t0), backend="numba").y[:, -1]
    run = simulate_impact(params, y, (t0, t0 + 2 * np.pi * 3), backend="scipy")
    K = ImpactModel(params).augmented()
    X = []
    for t in t0 + TAU:
        k = np.searchsorted(run.t, t, side="right") - 1
        z = np.concatenate([run.y[:, k], [np.cos(run.t[k]), np.sin(run.t[k])]])
        X.append((expm(K * (t - run.t[k])) @ z)[0])
    X = np.array(X)
    assert np.abs(X[:96] - X[48:]).max() < 1e-6  # a 2pi-orbit: settled
    return SteadyRecord(TAU, X, None, "expm")


@pytest.fixture(scope="module")
def impact_record():
    return _settled_impact(IMPACT)


def _difference_check(record, params, model, names, tol):
    orbit = RecordOrbit(record, params, model)
    orbit.samples(params)
    analytic = orbit.gradient(names)
    for k, name in enumerate(names):
        h = 1e-5 * getattr(params, name)
        ends = []
        for sign in (1, -1):
            other = RecordOrbit(record, params, model)
            ends.append(other.samples(params.replace(**{name: getattr(params, name) + sign * h})))
        numeric = (ends[0] - ends[1]) / (2 * h)
        assert np.abs(analytic[:, k] - numeric).max() <= tol * np.abs(numeric).max(), name


def test_the_samples_derivatives_of_9_match_differences_of_orbits(smooth_record):
    _difference_check(smooth_record, SMOOTH, "smooth", ["lam", "gamma", "eps", "Abar"], 1e-4)


def test_the_samples_derivatives_of_8_match_differences_of_orbits(impact_record):
    _difference_check(impact_record, IMPACT, "impact", ["lam", "chi", "eps"], 1e-4)


def test_a_clean_record_of_9_gives_back_three_parameters_from_half_off(smooth_record):
    start = SMOOTH.replace(lam=0.6, gamma=0.125, eps=0.06)
    fit = fit_steady_record(smooth_record, start, ["lam", "gamma", "eps"])
    assert fit.converged and fit.stable and fit.rms < 1e-7
    for name in ("lam", "gamma", "eps"):
        assert fit.values[name] == pytest.approx(getattr(SMOOTH, name), rel=1e-2), name


def test_the_orbit_a_record_follows_is_chosen_by_its_whole_shape():
    """At sigma = 0.5 two stable orbits of (9) have the same A1 to 1e-7, mirror twins (y(tau) ->
    -y(tau + pi)), the particle moving differently and the vessel's motion differing by 4e-3;
    which of them the search at the set finds is rounding. The record settled from rest and its
    mirror image (a record of the twin) are each compared with their own orbit, not the one the
    search found, and lam and gamma come back from 20 % off."""
    params = SMOOTH.replace(sigma=0.5)
    record = _settled_smooth(params)
    twin = SteadyRecord(record.tau - np.pi, -record.X, None, "mirror image")
    chosen = []
    for rec in (record, twin):
        orbit = RecordOrbit(rec, params)
        assert np.abs(orbit.samples(params) - rec.X).max() < 1e-7
        chosen.append(orbit.orbits.x[0][:4])
    # two orbits (their first harmonic alone cannot tell them apart)
    assert abs(record.first_harmonic() - twin.first_harmonic()) < 1e-6
    assert np.abs(chosen[0] - chosen[1]).max() > 0.1
    fit = fit_steady_record(record, params.replace(lam=0.48, gamma=0.2), ["lam", "gamma"])
    assert fit.converged and fit.stable and fit.rms < 1e-7
    for name in ("lam", "gamma"):
        assert fit.values[name] == pytest.approx(getattr(params, name), rel=1e-4), name


def test_a_clean_record_of_8_gives_back_three_parameters(impact_record):
    start = IMPACT.replace(lam=0.4, gamma=0.2, eps=0.035)
    fit = fit_steady_record(impact_record, start, ["lam", "gamma", "eps"], model="impact")
    assert fit.converged and fit.stable and fit.rms < 1e-4
    for name in ("lam", "gamma", "eps"):
        assert fit.values[name] == pytest.approx(getattr(IMPACT, name), rel=1e-2), name


def test_a_record_of_8_is_compared_with_the_orbit_it_settled_on():
    """At sigma = 4 two stable orbits of (8) coexist (A1 0.82 and 0.45): the record settled from
    rest (the expm event loop) is its own orbit's, the other among the candidates."""
    params = IMPACT.replace(sigma=4.0)
    record = _settled_impact(params)
    orbit = RecordOrbit(record, params, model="impact")
    assert np.abs(orbit.samples(params) - record.X).max() < 1e-6
    assert any(stable and A1 > 1.5 * record.first_harmonic() for A1, stable in orbit.candidates)


def _noisy(record, seed, level=0.01):
    std = level * float(np.abs(record.X).max())
    X = record.X + np.random.default_rng(seed).normal(0.0, std, size=len(record))
    return SteadyRecord(record.tau, X, np.full(len(record), std), "noisy", record.sigmas)


def test_records_at_two_frequencies_give_back_three_parameters_from_half_off(two_records):
    start = SMOOTH.replace(lam=0.6, gamma=0.125, eps=0.06)
    fit = fit_steady_record(two_records, start, ["lam", "gamma", "eps"])
    assert fit.converged and fit.stable and fit.rms < 1e-7
    assert [curve["sigma"] for curve in fit.orbits] == [-1.0, 0.6]
    for name in ("lam", "gamma", "eps"):
        assert fit.values[name] == pytest.approx(getattr(SMOOTH, name), rel=1e-2), name


@pytest.mark.slow  # the default run keeps this capability's faster tests
def test_a_second_frequency_separates_the_dampings_and_bounds_eps(smooth_record, two_records):
    """With 1 % noise one frequency's record leaves lam within most of its admissible range and
    eps unbounded below (lam and gamma correlated to -0.9999); with a second frequency the profiles
    narrow by more than five times and hold the truth."""
    start = SMOOTH.replace(lam=0.48, gamma=0.2, eps=0.048)
    one = fit_steady_record(_noisy(smooth_record, 1), start, ["lam", "gamma", "eps"])
    two = fit_steady_record(_noisy(two_records, 1), start, ["lam", "gamma", "eps"])
    assert one.describes and two.describes
    assert (one.estimate["eps"]["profile_95"][0] or 0.0) < 1e-3
    assert abs(two.correlation[0][1]) < 0.99 < abs(one.correlation[0][1])
    for name in ("lam", "gamma", "eps"):
        lo, hi = two.estimate[name]["profile_95"]
        wide = one.estimate[name]["profile_95"]
        assert lo < getattr(SMOOTH, name) < hi, name
        assert 5 * (hi - lo) < (wide[1] or np.inf) - (wide[0] or 0.0), name


@pytest.mark.slow  # 8-28 s; the file's other tests keep the capability in the default run
def test_a_wrong_wall_power_is_said_not_to_fit(smooth_record):
    """The record of n = 20 with 1 % noise fitted with n = 50 held: lam and gamma absorb much of
    it (lam 0.03, gamma 0.38), not all: the chi-square's p-value below 1e-3."""
    fit = fit_steady_record(_noisy(smooth_record, 0), SMOOTH.replace(n=50), ["lam", "gamma"])
    assert not fit.describes and "does not describe" in fit.goodness.statement


def _write(path, record):
    sigmas = record.sigmas if record.sigmas is not None else [None] * len(record)
    rows = "".join(
        f"{float(t)!r},{float(x)!r},{float(s)!r}" + (f",{float(g)!r}" if g is not None else "") + "\n"
        for t, x, s, g in zip(record.tau, record.X, record.std, sigmas)
    )
    path.write_text("tau,X,std" + (",sigma" if record.sigmas is not None else "") + "\n" + rows)


def test_slosh_bif_fit_records_at_two_frequencies_from_one_file(tmp_path, two_records, capsys):
    data = tmp_path / "records.csv"
    _write(data, _noisy(two_records, 2))
    read = read_steady_record(data)
    assert [sigma for sigma, _ in read.parts(5.0)] == [-1.0, 0.6]
    sets = [f"--set={k}={getattr(SMOOTH, k)}" for k in ("eps", "beta", "n", "lam")]
    args = ["fit", "--preset", "fig10", *sets, "--set=gamma=0.3", "--data", str(data), "--record", "steady"]
    assert main(args + ["--free", "gamma", "--out", str(tmp_path / "fit")]) == 0
    assert "288 samples of 2 settled records (sigma = -1, 0.6)" in capsys.readouterr().out
    record = json.loads((tmp_path / "fit" / "fit.json").read_text())
    assert [curve["sigma"] for curve in record["orbits"]] == [-1.0, 0.6]
    lo, hi = record["estimate"]["gamma"]["profile_95"]
    assert lo < SMOOTH.gamma < hi
    few = tmp_path / "few.csv"
    rows = [f"{k * 0.3},1.0,{-1.0}" for k in range(20)] + [f"{k * 2 * np.pi},1.0,0.6" for k in range(12)]
    few.write_text("tau,X,sigma\n" + "\n".join(rows) + "\n")
    with pytest.raises(ValueError, match="1 distinct phases of tau modulo 2pi at sigma = 0.6"):
        read_steady_record(few)


def test_slosh_bif_fit_a_settled_record_and_its_refusals(tmp_path, smooth_record, capsys):
    data = tmp_path / "record.csv"
    _write(data, _noisy(smooth_record, 0))
    assert read_steady_record(data).first_harmonic() == pytest.approx(
        smooth_record.first_harmonic(), rel=0.02
    )
    sets = [f"--set={k}={getattr(SMOOTH, k)}" for k in ("eps", "beta", "n", "lam", "sigma")]
    args = ["fit", "--preset", "fig10", *sets, "--set=gamma=0.3", "--data", str(data), "--record", "steady"]
    out = tmp_path / "fit"
    assert main(args + ["--free", "gamma", "--out", str(out)]) == 0
    record = json.loads((out / "fit.json").read_text())
    gamma = record["estimate"]["gamma"]
    assert gamma["profile_95"][0] < SMOOTH.gamma < gamma["profile_95"][1]
    assert record["record"] == "steady" and record["orbit_stable"] and len(record["orbits"][0]["X"]) == 257
    assert (out / "fit.png").is_file() and (out / "params.toml").is_file()
    side = tmp_path / "side"  # the starts and the profile on two processes: the same fit
    assert main(args + ["--free", "gamma", "--workers", "2", "--out", str(side)]) == 0
    assert json.loads((side / "fit.json").read_text())["estimate"] == record["estimate"]
    capsys.readouterr()
    for extra, message in (
        (["--free", "n"], "--free takes a comma-separated subset of lam, chi, gamma, Abar, eps"),
        (["--free", "gamma", "--model", "slowflow"], "fitted by the orbits"),
        (["--free", "gamma", "--set=Abar=0"], "needs the forcing Abar > 0"),
    ):
        assert main(args + extra + ["--out", str(tmp_path / "x")]) == 2
        assert message in capsys.readouterr().err
    short = [
        "fit",
        "--preset",
        "fig10",
        "--record",
        "steady",
        "--free",
        "gamma",
        "--out",
        str(tmp_path / "y"),
    ]
    few = tmp_path / "few.csv"
    few.write_text("tau,X\n" + "".join(f"{k * 2 * np.pi},{1.0 + k}\n" for k in range(12)))
    assert main(short + ["--data", str(few)]) == 2
    assert "1 distinct phases of tau modulo 2pi" in capsys.readouterr().err
    envelope = tmp_path / "envelope.csv"
    envelope.write_text("tau,A\n0,1\n1,2\n2,3\n")
    assert main(short + ["--data", str(envelope)]) == 2
    assert "missing X" in capsys.readouterr().err


@pytest.mark.slow
def test_coverage_over_40_seeds_of_noise_on_a_settled_record(smooth_record):
    """lam, gamma and eps from 20 % off on 40 noisy copies (1 %) of the clean (9) record: each
    profile interval misses the truth in at most 5, not counting fits that say why (an estimate at
    its range's end, a profile that lost its orbit, a misfit)."""
    names = ["lam", "gamma", "eps"]
    start = SMOOTH.replace(**{n: 1.2 * getattr(SMOOTH, n) for n in names})
    misses = dict.fromkeys(names, 0)
    for seed in range(40):
        fit = fit_steady_record(_noisy(smooth_record, seed), start, names)
        said = (
            not fit.describes
            or "sits at the" in fit.not_identifiable
            or "profile stops" in fit.not_identifiable
        )
        for name in names:
            lo, hi = fit.estimate[name]["profile_95"]
            truth = getattr(SMOOTH, name)
            inside = (lo is None or lo <= truth) and (hi is None or truth <= hi)
            misses[name] += not inside and not said
    assert max(misses.values()) <= 5, misses


@pytest.mark.slow
def test_coverage_over_40_seeds_of_noise_on_records_at_two_frequencies(two_records):
    """lam, gamma and eps from 20 % off on 40 noisy copies (1 %) of the two clean records: each
    profile interval misses the truth in at most 5, not counting fits that say why."""
    names = ["lam", "gamma", "eps"]
    start = SMOOTH.replace(**{n: 1.2 * getattr(SMOOTH, n) for n in names})
    misses = dict.fromkeys(names, 0)
    for seed in range(40):
        fit = fit_steady_record(_noisy(two_records, seed), start, names)
        said = not fit.describes or "sits at the" in fit.not_identifiable
        for name in names:
            lo, hi = fit.estimate[name]["profile_95"]
            inside = (lo is None or lo <= getattr(SMOOTH, name)) and (
                hi is None or getattr(SMOOTH, name) <= hi
            )
            misses[name] += not inside and not said
    print(f"profile misses over 40 seeds, fits that say why not counted: {misses}")
    assert max(misses.values()) <= 5, misses
