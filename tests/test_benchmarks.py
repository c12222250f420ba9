"""Work-precision benchmarks: helpers against closed forms, the commands' files, and the
frequency-response reference against an independent evaluation."""

import csv

import numpy as np
import pytest

from benchmarks import frequency_response, timing
from benchmarks import output as bench_output
from benchmarks import run as bench
from slosh_bif import get_preset


def test_first_harmonic_of_a_closed_form_signal():
    t = np.arange(0.0, 40 * np.pi, 0.02)
    X = 0.7 * np.sin(t + 0.3) + 0.2 * np.cos(3 * t) + 0.1  # the 3rd harmonic and the mean do not leak
    assert timing.first_harmonic(t, X, periods=10) == pytest.approx(0.7, rel=1e-4)
    with pytest.raises(ValueError, match="forcing periods"):
        timing.first_harmonic(t[:100], X[:100], periods=10)


def test_equal_error_ratio_recovers_a_known_speedup():
    # Baseline: time = 1e-3 * error**-0.25; the method is exactly 40 times faster at any error,
    # sampled at other errors than the baseline (so the ratio needs interpolation of both).
    rows = [
        dict(preset="p", method="base", error=e, seconds=1e-3 * e**-0.25) for e in (1e-10, 1e-8, 1e-6, 1e-4)
    ]
    rows += [
        dict(preset="p", method="fast", error=e, seconds=1e-3 * e**-0.25 / 40)
        for e in (3e-11, 3e-9, 3e-7, 3e-5)
    ]
    assert bench_output.equal_error_ratio(rows, "p", "fast", baseline="base") == pytest.approx(40, rel=1e-9)
    far = [dict(preset="p", method="far", error=e, seconds=1.0) for e in (1e-2, 1e-1)]
    assert np.isnan(bench_output.equal_error_ratio(rows + far, "p", "far", baseline="base"))


def test_timed_reports_the_median_and_stops_at_the_budget():
    calls = []
    seconds, result, runs = timing.timed(
        lambda: calls.append(1) or len(calls), repeats=5, min_seconds=0.0, budget=0.0
    )
    assert runs == 1 and result == 1 and seconds >= 0


def test_reference_orbit_is_converged_and_agrees_with_a_long_simulation():
    """The reference of the frequency-response question, against a different evaluation of the same
    quantity: the first harmonic of a long simulation of (9) at tight tolerance."""
    ref = frequency_response.reference_orbits("fig10", [4.0])[0]
    assert ref.self_error < 1e-8 and ref.max_multiplier < 1
    pre = get_preset("fig10")
    from slosh_bif.simulation.direct import SimulationSettings, simulate

    sim = simulate(
        pre.params.replace(sigma=4.0),
        pre.state0,
        400 * 2 * np.pi,
        settings=SimulationSettings(rtol=1e-11, atol=1e-13),
    )
    assert timing.first_harmonic(sim.t, sim.y[0], 20) == pytest.approx(ref.A1, rel=1e-5)


def _read(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.mark.slow  # the whole bench (78 s); its parts have the fast tests above and below
def test_bench_command_writes_every_chart_and_table(tmp_path, capsys):
    from benchmarks.__main__ import main as bench_main

    assert bench_main(["--out", str(tmp_path), "--quick"]) == 0
    for name in ("integrators", "frequency_response", "growth"):
        assert (tmp_path / f"{name}.png").stat().st_size > 10_000
    integ = _read(tmp_path / "integrators.csv")
    assert {r["method"] for r in integ} >= {
        "slosh_bif DOP853 (numba, default)",
        "scipy DOP853",
        "scipy Radau (analytic Jacobian)",
    }
    # The compiled and the scipy-fallback DOP853 are the same method: equal evaluation counts within
    # a few steps and errors of the same size, whatever their speeds.
    for preset in ("fig10", "fig12"):
        for rtol in ("1e-06", "1e-09"):
            a, b = (
                next(r for r in integ if r["preset"] == preset and r["rtol"] == rtol and r["method"] == m)
                for m in ("slosh_bif DOP853 (numba, default)", "slosh_bif DOP853 (scipy fallback)")
            )
            assert abs(int(a["nfev"]) - int(b["nfev"])) <= 0.05 * int(b["nfev"])
    fr = _read(tmp_path / "frequency_response.csv")
    shooting = [r for r in fr if r["method"] == "shooting on (9)"]
    assert shooting and all(float(r["error"]) < 1e-3 and r["failures"] == "0" for r in shooting)
    # The slow flows' errors in the tables slosh_bif.studies.ladder chooses by must cover what is measured
    # here.
    from slosh_bif.studies.ladder import CORRECTED_ERROR, SLOW_FLOW_ERROR

    for preset in (
        "fig10",
        "fig13",
    ):  # the finest continuation step: the model's error, not the interpolation's
        for method, table in (
            ("eq. 46 continuation", SLOW_FLOW_ERROR),
            ("corrected slow flow continuation", CORRECTED_ERROR),
        ):
            finest = min(
                (float(r["value"]), float(r["error"]))
                for r in fr
                if r["method"] == method and r["preset"] == preset
            )
            assert finest[1] <= table["frequency-response"]
    crit = _read(tmp_path / "critical_forcing.csv")
    assert crit and max(float(r["relative_difference"]) for r in crit) <= SLOW_FLOW_ERROR["critical-forcing"]
    assert max(float(r["relative_difference_corrected"]) for r in crit) <= CORRECTED_ERROR["critical-forcing"]
    refs = _read(tmp_path / "frequency_response_reference.csv")
    assert all(float(r["self_error"]) < 1e-8 and float(r["max_multiplier"]) < 1 for r in refs)
    assert {r["study"] for r in _read(tmp_path / "growth.csv")} == {"n", "interval", "regime map"}
    assert "speedup_vs_scipy_DOP853" in capsys.readouterr().out


def test_bench_rejects_bad_input(tmp_path):
    with pytest.raises(ValueError, match="unknown benchmark 'sped'"):
        bench.run(tmp_path, only=["sped"])
    with pytest.raises(ValueError, match="repeats"):
        bench.run(tmp_path, repeats=0)


def test_speed_bench_times_the_command_as_a_user_runs_it():
    """The speed question runs the CLI in a fresh interpreter; a failing command is an error that
    names it, not a time."""
    from benchmarks.speed import run_cli

    seconds, _ = run_cli(["info", "--preset", "fig10"])
    assert 0 < seconds < 120
    with pytest.raises(RuntimeError, match="slosh-bif info --preset nosuch failed"):
        run_cli(["info", "--preset", "nosuch"])


def test_the_stage_profile_of_a_shoot_run_has_every_stage(tmp_path):
    """The profile's marks come from the parent (the figure is drawn by a forked child): a short
    branch's run gives every stage a time, and they add up to less than the whole process."""
    from benchmarks.speed_reference import STAGES, stage_profile

    arguments = ["shoot", "--preset", "fig10", "--no-switch", "--sigma-min", "2", "--sigma-max", "3"]
    seconds = stage_profile([*arguments, "--out", str(tmp_path)])
    assert set(seconds) == set(STAGES)
    assert all(value >= 0 for key, value in seconds.items() if key != "interpreter and unmeasured")
    assert seconds["continuation"] > 0 and seconds["plot"] > 0


def test_the_bench_against_an_earlier_commit_unpacks_its_tree_or_says_why_not(tmp_path):
    from benchmarks import against

    tree = against.unpack("HEAD", tmp_path)
    assert (tree / "slosh_bif" / "cli" / "__init__.py").is_file() and (tree / "pyproject.toml").is_file()
    with pytest.raises(ValueError, match="--base no-such-commit"):
        against.unpack("no-such-commit", tmp_path)


def test_the_bench_against_an_earlier_commit_times_each_branch_whole_and_stopped_after_one_step(
    tmp_path, monkeypatch
):
    """A branch case's floor is this tree's run stopped after one continuation step over the base's
    whole run: the bookkeeping checked with made-up times (no process is started)."""
    from benchmarks import against

    times = {("base", False): 2.0, ("base", True): 1.0, ("this", False): 3.0, ("this", True): 1.5}
    seen = []

    def fake_run(tree, arguments, out, timeout=0.0):
        one_step = arguments[-2:] == against.ONE_STEP
        seen.append((tree.name, one_step))
        return times["base" if tree.name == "base" else "this", one_step]

    monkeypatch.setattr(against, "unpack", lambda commit, where: tmp_path / "base")
    monkeypatch.setattr(against, "ROOT", tmp_path / "this")
    monkeypatch.setattr(against, "_prepare", lambda tree: None)
    monkeypatch.setattr(against, "timed_run", fake_run)
    monkeypatch.setattr(against, "_n6_guess", lambda: ["--guess", "0,0,0,0"])
    rows = {r["case"]: r for r in against.against_bench(quick=True)}
    branch = rows["Fig. 10 branch (n = 50)"]
    assert branch["ratio"] == pytest.approx(1.5) and branch["floor_ratio"] == pytest.approx(0.75)
    assert (branch["fixed_seconds"], branch["base_fixed_seconds"]) == (1.5, 1.0)
    assert len(rows) == 2 and {("base", True), ("this", True), ("base", False), ("this", False)} <= set(seen)
