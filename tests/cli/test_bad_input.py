"""Bad input gets a one-line error naming what was wrong, before any work (cases a user met)."""

import json
import subprocess
import sys
import time

import pytest

from slosh_bif.cli import main
from slosh_bif.studies.chart.output import curve_store

TANK = [
    "tank",
    "--shape",
    "cylinder",
    "--depth",
    "8",
    "--structure-mass",
    "2e6",
    "--structure-frequency",
    "0.8",
    "--excitation-frequency",
    "0.72",
    "--ground-acceleration",
    "1.5",
    "--clearance",
    "1",
]
GUESS = ["shoot", "--preset", "fig10", "--guess", "0.1,0,0,0"]


@pytest.mark.parametrize(
    "argv, words",
    [
        (["simulate", "--preset", "fig10", "--tmax", "1e-9"], "--tmax must be above"),
        (["simulate", "--preset", "fig10", "--tmax", "20", "--backend", "scipy"], "--tmax must be above"),
        (["simulate", "--preset", "fig10", "--set", "sigma=1e6"], "eps * sigma = 50000 >= 1"),
        (["basins", "--preset", "fig10", "--set", "sigma=30", "--grid", "3", "3"], "eps * sigma = 1.5 >= 1"),
        (["answer", "regime", "--preset", "fig10", "--set", "sigma=30"], "eps * sigma = 1.5 >= 1"),
        (["chart", "--preset", "fig13", "--set", "eps=1.2", "--sigma-max", "2"], "eps * sigma = 1.2 >= 1"),
        ([*TANK, "--radius", "1e9"], "too shallow for the sloshing-mode series"),
        (
            ["shoot", "--preset", "fig10", "--model", "impact", "--start", "scan"],
            "--model impact starts from a simulation of (8)",
        ),
        (
            [*GUESS, "--model", "impact", "--sigma-min", "2", "--sigma-max", "3"],
            "must lie in the range [2, 3] (--sigma-min/--sigma-max)",
        ),
        (
            [*GUESS, "--parameter", "Abar", "--abar-min", "4", "--abar-max", "5"],
            "--guess is an orbit at the set's Abar = 3 (the preset's, the parameter file's or --set), which",
        ),
        (
            [
                "chart",
                "--preset",
                "fig13",
                "--model",
                "impact",
                "--sigma-min",
                "-3",
                "--sigma-max",
                "5",
                "--backend",
                "scipy",
            ],
            "the orbits of the impact models have one exact flow",
        ),
    ],
)
def test_a_one_line_error_before_any_work(argv, words, tmp_path, capsys):
    started = time.perf_counter()
    code = main([*argv, "--out", str(tmp_path / "out")] if argv[0] != "answer" else argv)
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err
    assert time.perf_counter() - started < 30  # a bound against a simulation before the check, not a timing
    assert not (tmp_path / "out" / "trajectory.npz").exists()


def test_a_binary_parameter_file_names_the_file_and_the_option(tmp_path, capsys):
    path = tmp_path / "params.toml"
    path.write_bytes(b"\x00\x01\xff\xfe")
    assert main(["info", "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert "--params" in err and str(path) in err


def test_an_empty_out_is_refused(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["frc", "--preset", "fig10", "--out", ""])
    assert stop.value.code == 2 and "--out" in capsys.readouterr().err


def test_frc_in_abar_needs_no_upper_end(tmp_path):
    assert main(["frc", "--preset", "fig13", "--parameter", "Abar", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "frc.csv").stat().st_size > 100


def test_damaged_stores_are_one_line_errors_naming_the_file(tmp_path, capsys):
    out = tmp_path / "map"
    arguments = [
        "regimes",
        "--preset",
        "fig13",
        "--sigma-points",
        "2",
        "--abar-points",
        "1",
        "--tmax",
        "60",
        "--workers",
        "1",
        "--out",
        str(out),
    ]
    assert main(arguments) == 0
    store = out / "regimes.json"
    good = json.loads(store.read_text())
    for cells in ([1, 2], {"a,b": {}}, {"0,0": [1]}):
        store.write_text(json.dumps({**good, "cells": cells}))
        assert main([*arguments, "--resume"]) == 2
        err = capsys.readouterr().err
        assert f"--resume: {store} is damaged" in err and "Traceback" not in err
    settings = {"any": 1}
    curve_store(tmp_path / "curves", settings, resume=False)
    (tmp_path / "curves" / "curve-0003.npz").write_bytes(b"PK\x03\x04 truncated")
    with pytest.raises(ValueError, match="curve-0003.npz is damaged"):
        curve_store(tmp_path / "curves", settings, resume=True)


def test_a_closed_pipe_ends_quietly():
    # The reader exits before reading anything: every write of the command meets a closed pipe.
    run = subprocess.run(
        [
            "bash",
            "-c",
            f"sleep 0.5 | ('{sys.executable}' -m slosh_bif.cli info --preset fig10; echo \"status "
            '$?" >&2) | true',
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert "status 0" in run.stderr and "Broken pipe" not in run.stderr and "Traceback" not in run.stderr, (
        run.stderr
    )
