"""Every numeric option, any value (hypothesis): either a one-line error and exit status 2 before
any work, or the work starts (a stand-in raises at its first step). Values no command can use
(NaN, infinities, negative sizes) must be errors (issue 18). Derandomized, so that CI runs the
same examples every time; values random runs found are kept in the sampled list."""

import importlib
import math
import pkgutil

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import slosh_bif
from slosh_bif.cli import main


class _WorkStarted(Exception):
    pass


def _started(*_args, **_kwargs):
    raise _WorkStarted


class _NoFigure:
    """In place of shoot's figure process (forked before the work starts: a quarter of a second
    a run, which is all an option check costs otherwise)."""

    def __enter__(self):
        return self

    def __exit__(self, *_exc):
        return False

    def submit(self, *_args, **_kwargs):
        pass

    def result(self):
        return None


@pytest.fixture
def no_work(monkeypatch):
    """The first step of each command's work raises _WorkStarted."""
    # Every module imported before anything is patched: a module imported first under a patch
    # binds the stand-in by name and keeps it after the test (later tests in the same process, the
    # README's commands, then failed with _WorkStarted).
    for module in pkgutil.walk_packages(slosh_bif.__path__, "slosh_bif."):
        if not module.name.endswith("__main__"):
            importlib.import_module(module.name)
    import slosh_bif.flows.smooth.integrator as integrator
    import slosh_bif.orbits.scan as scan
    import slosh_bif.orbits.starts as starts
    import slosh_bif.report.plot_process as plot_process
    import slosh_bif.simulation.sweep as sweep
    import slosh_bif.slowflow.steady_states as steady_states
    import slosh_bif.studies.chart.smooth as chart
    import slosh_bif.studies.ladder as ladder

    monkeypatch.setattr(plot_process, "PlotProcess", _NoFigure)
    monkeypatch.setattr(integrator, "integrate_grid", _started)  # simulate's integration
    monkeypatch.setattr(sweep, "ProcessPoolExecutor", _started)  # the pools of regimes, basins and trust
    monkeypatch.setattr(chart, "start_orbit", _started)  # the chart's first orbit
    for name in ("start_orbit", "slow_flow_start"):  # shoot's first orbit
        monkeypatch.setattr(starts, name, _started)
    monkeypatch.setattr(scan, "scan_families", _started)
    import slosh_bif.model.tank as tank
    import slosh_bif.slowflow.critical as critical

    monkeypatch.setattr(critical, "critical_curve", _started)  # critical's continuation

    monkeypatch.setattr(tank, "tank_model", _started)  # tank's conversion, after the inputs are checked
    for name in ("frequency_response", "forcing_response"):  # frc's continuation
        monkeypatch.setattr(steady_states, name, _started)
    for name in (
        "frequency_response",
        "critical_forcing",
        "critical_forcing_full",
        "simulate",
        "settle_and_shoot",
        "trace_orbits",
        "impact_start",
    ):  # answer's rungs
        monkeypatch.setattr(ladder, name, _started)


NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.sampled_from([0.0, -0.0, -1.0, 1e-300, 1e300, 1.19e305, 0.5, 3.0, 600.0, -6.0, 8.0]),
)

_TANK_REST = [
    "--depth",
    "8",
    "--structure-mass",
    "2e6",
    "--structure-frequency",
    "0.8",
    "--excitation-frequency",
    "0.72",
    "--clearance",
    "1",
    "--ground-acceleration",
    "1",
]

# (command line before the value, option, command line after it, the values that must be errors)
CASES = {
    "simulate --tmax": (
        ["simulate", "--preset", "fig10"],
        "--tmax",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "simulate --noise": (
        ["simulate", "--preset", "fig10", "--tmax", "10"],
        "--noise",
        [],
        lambda v: not (math.isfinite(v) and v >= 0),
    ),
    "simulate --noise-cutoff": (
        ["simulate", "--preset", "fig10", "--tmax", "10", "--noise", "0.1"],
        "--noise-cutoff",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "simulate --set Abar": (
        ["simulate", "--preset", "fig10", "--tmax", "10", "--set"],
        None,
        [],
        lambda v: not (math.isfinite(v) and v >= 0),
    ),
    "regimes --abar-max": (
        ["regimes", "--preset", "fig10", "--abar-min", "0.1"],
        "--abar-max",
        [],
        lambda v: not (math.isfinite(v) and v > 0.1),
    ),
    "regimes --tmax": (
        ["regimes", "--preset", "fig10"],
        "--tmax",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "chart --sigma-max": (
        ["chart", "--preset", "fig10", "--sigma-min", "-6"],
        "--sigma-max",
        [],
        lambda v: not (math.isfinite(v) and v > -6),
    ),
    "chart --abar-min": (
        ["chart", "--preset", "fig10"],
        "--abar-min",
        [],
        lambda v: not (math.isfinite(v) and 0 <= v < 6),
    ),
    "chart --second-max": (
        ["chart", "--preset", "fig10", "--second", "beta", "--second-min", "0"],
        "--second-max",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "shoot --sigma-max": (
        ["shoot", "--preset", "fig10", "--sigma-min", "-6"],
        "--sigma-max",
        [],
        lambda v: not (math.isfinite(v) and v > -6),
    ),
    "shoot --rtol": (["shoot", "--preset", "fig10"], "--rtol", [], lambda v: not (1e-14 <= v <= 1e-4)),
    "frc --sigma-min": (
        ["frc", "--preset", "fig10", "--sigma-max", "8"],
        "--sigma-min",
        [],
        lambda v: not (math.isfinite(v) and v < 8),
    ),
    "trust --sigma-max": (
        ["trust", "--preset", "fig13", "--no-switch", "--sigma-min", "-6"],
        "--sigma-max",
        [],
        lambda v: not (math.isfinite(v) and v > -6),
    ),
    "basins --tmax": (
        ["basins", "--preset", "fig10"],
        "--tmax",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "critical --sigma-max": (
        ["critical", "--preset", "fig13", "--sigma-min", "-6"],
        "--sigma-max",
        [],
        lambda v: not (math.isfinite(v) and v > -6),
    ),
    "compare --sigma-min": (
        ["compare", "--preset", "fig13", "--sigma-max", "8"],
        "--sigma-min",
        [],
        lambda v: not (math.isfinite(v) and v < 8),
    ),
    "frc --ds": (["frc", "--preset", "fig10"], "--ds", [], lambda v: not (math.isfinite(v) and v > 0)),
    "frc --ds-max": (
        ["frc", "--preset", "fig10"],
        "--ds-max",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "frc --max-seconds": (["frc", "--preset", "fig10"], "--max-seconds", [], lambda v: not v > 0),
    "simulate --transient": (
        ["simulate", "--preset", "fig10", "--tmax", "10"],
        "--transient",
        [],
        lambda v: not 0 <= v < 10,
    ),
    "chart --tmax": (
        ["chart", "--preset", "fig10", "--regimes", "3", "3"],
        "--tmax",
        [],
        lambda v: not (math.isfinite(v) and 0 < v <= 0.02 * 20_000_000),
    ),
    "tank --depth": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST[2:]],
        "--depth",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "tank --density": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST],
        "--density",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "tank --radius": (
        ["tank", "--shape", "cylinder", *_TANK_REST],
        "--radius",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "tank --ground-acceleration": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST[:-2]],
        "--ground-acceleration",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "tank --damping-ratio": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST],
        "--damping-ratio",
        [],
        lambda v: not (math.isfinite(v) and 0 <= v < 1),
    ),
    "answer --tol": (
        ["answer", "frequency-response", "--preset", "fig10"],
        "--tol",
        [],
        lambda v: not (math.isfinite(v) and v > 0),
    ),
    "answer --tmax": (
        ["answer", "regime", "--preset", "fig10"],
        "--tmax",
        [],
        lambda v: not (math.isfinite(v) and v > 8 * math.pi),
    ),
    "basins --range1": (
        ["basins", "--preset", "fig10", "--range1", "-3"],
        None,
        [],
        lambda v: not (math.isfinite(v) and v > -3),
    ),
    "basins --range2": (
        ["basins", "--preset", "fig10", "--range2", "-1"],
        None,
        [],
        lambda v: not (math.isfinite(v) and v > -1),
    ),
    "tank --lam": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST],
        "--lam",
        [],
        lambda v: not _wall_ok(lam=v),
    ),
    "tank --chi": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST],
        "--chi",
        [],
        lambda v: not _wall_ok(chi=v),
    ),
    "answer --sigma-min": (
        ["answer", "frequency-response", "--preset", "fig10", "--sigma-max", "8"],
        "--sigma-min",
        [],
        lambda v: not (math.isfinite(v) and v < 1),
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
@settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(value=NUMBERS)
def test_a_numeric_option_is_an_error_or_starts_the_work(case, value, no_work, tmp_path, capsys):
    before, option, after, invalid = CASES[case]
    text = repr(value) if math.isfinite(value) else str(value)
    # no option: the value ends the line before it (--set Abar=VALUE, or the second number of a pair)
    last = before[-1] == "--set"
    argv = (
        before
        + ([option, text] if option else [f"Abar={text}"] if last else [text])
        + after
        + ["--out", str(tmp_path / "out")]
    )
    _an_error_or_the_work(argv, invalid(value), capsys)


def _an_error_or_the_work(argv, invalid: bool, capsys, *, usable_refused_too: bool = False):
    """Run ``argv``: an invalid value must be a one-line error (exit 2) before the work starts;
    with ``usable_refused_too``, a valid one must start the work."""
    try:
        status = main(argv)
    except _WorkStarted:
        status = None
    err = capsys.readouterr().err
    if status is None:
        assert not invalid, f"{argv}: the work started with a value no command can use"
    else:
        assert status == 2 and "Traceback" not in err and err.strip().count("\n") == 0, (argv, status, err)
        assert invalid or not usable_refused_too, f"{argv}: refused a usable value: {err}"


@pytest.mark.parametrize("value", ["1", "0", "-3"])
def test_compare_refuses_too_few_sigma_points_before_any_work(value, no_work, tmp_path, capsys):
    # (it used to check --sigma-points after the frequency response and the orbit family were computed)
    assert (
        main(["compare", "--preset", "fig13", "--sigma-points", value, "--out", str(tmp_path / "out")]) == 2
    )
    assert "--sigma-points must be an integer >= 2" in capsys.readouterr().err


def _wall_ok(n=50, pbar=0, lam=0.35, chi=0.2):
    """The paper's wall (lam 0.35, chi 0.2, n 50, pbar 0) with one of them changed: finite lam >= 0
    and chi > 0, eq. (19) converges, p is a whole number and eq. (21)'s restitution coefficient
    is real (the admissibility that Params enforces)."""
    from slosh_bif.model.restitution import dissipation_at_unit_speed

    if not (math.isfinite(lam) and lam >= 0 and math.isfinite(chi) and chi > 0):
        return False
    if not (n >= 1 and pbar > -(n + 1) and (pbar + n) % 2 == 0):
        return False
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
            return bool(dissipation_at_unit_speed(lam, chi, n, pbar) < 1)
    except OverflowError:  # a dissipation beyond every float: certainly not < 1
        return False


INTEGERS = st.one_of(st.integers(-(10**6), 10**6), st.sampled_from([-1, 0, 1, 2, 3, 64, 65, 10**9]))

# Integer options: (command line before the value, option, the values that must be errors)
INTEGER_CASES = {
    "shoot --segments": (["shoot", "--preset", "fig10"], "--segments", lambda v: not 1 <= v <= 64),
    "shoot --settle": (["shoot", "--preset", "fig10"], "--settle", lambda v: not 0 <= v <= 100_000),
    "shoot --max-branches": (["shoot", "--preset", "fig10"], "--max-branches", lambda v: not 1 <= v <= 1000),
    "shoot --scan-points": (
        ["shoot", "--preset", "fig10", "--start", "scan"],
        "--scan-points",
        lambda v: not 1 <= v <= 1000,
    ),
    "shoot --scan-random": (
        ["shoot", "--preset", "fig10", "--start", "scan"],
        "--scan-random",
        lambda v: not 0 <= v <= 1000,
    ),
    "compare --segments": (["compare", "--preset", "fig13"], "--segments", lambda v: not 1 <= v <= 64),
    "regimes --abar-points": (
        ["regimes", "--preset", "fig10"],
        "--abar-points",
        lambda v: not 1 <= v <= 2000,
    ),
    "basins --grid": (["basins", "--preset", "fig10", "--grid", "5"], "", lambda v: not 1 <= v <= 2000),
    "trust --sigma-points": (
        ["trust", "--preset", "fig13", "--no-switch"],
        "--sigma-points",
        lambda v: not 2 <= v <= 100_000,
    ),
    "trust --workers": (
        ["trust", "--preset", "fig13", "--no-switch"],
        "--workers",
        lambda v: not 1 <= v <= 256,
    ),
    "basins --workers": (["basins", "--preset", "fig10"], "--workers", lambda v: not 1 <= v <= 256),
    "tank --n": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST],
        "--n",
        lambda v: not _wall_ok(n=v),
    ),
    "tank --pbar": (
        ["tank", "--shape", "cylinder", "--radius", "5", *_TANK_REST],
        "--pbar",
        lambda v: not _wall_ok(pbar=v),
    ),
}


@pytest.mark.parametrize("case", sorted(INTEGER_CASES))
@settings(
    max_examples=30,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(value=INTEGERS)
def test_an_integer_option_is_an_error_or_starts_the_work(case, value, no_work, tmp_path, capsys):
    before, option, invalid = INTEGER_CASES[case]
    argv = (
        [*before, option, str(value)] if option else [*before, str(value)]
    )  # no option: the value ends the line before it
    _an_error_or_the_work(
        [*argv, "--out", str(tmp_path / "out")], invalid(value), capsys, usable_refused_too=True
    )
