"""Interruption (issue 18): a regime map or a trust map stopped by SIGINT or SIGTERM exits within
seconds with 130 / 143, leaves no worker process behind, and writes the points it finished, the
rest marked "not computed", in complete files."""

import csv
import os
import signal
import subprocess
import sys
import time

import pytest


def _children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as fh:
            return [int(c) for c in fh.read().split()]
    except OSError:
        return []


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split()[2] != "Z"
    except OSError:
        return False


REGIMES = ["regimes", "--preset", "fig13", "--sigma-points", "6", "--abar-points", "6", "--tmax", "3000"]
TRUST = [
    "trust",
    "--preset",
    "fig13",
    "--no-switch",
    "--eps",
    "0.02,0.05,0.1",
    "--beta",
    "0,0.3",
    "--n",
    "20,50",
]


def default_sigint():
    """Ctrl-C as a terminal gives it: a shell without job control starts background commands with
    SIGINT ignored (POSIX), and an ignored SIGINT is inherited by every child, so a suite run with
    ``&`` would see the map run to its end (exit 0) instead of stopping."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _stop_while_running(arguments, signum, out, wait=4.0, ready=None):
    """Start the map, wait for its pool, then ``wait`` seconds, or (``ready``) until ready() holds
    (at most 120 s: a loaded machine may take longer than any fixed wait for its first cell)."""
    child = subprocess.Popen(
        [sys.executable, "-m", "slosh_bif.cli", *arguments, "--workers", "2", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=default_sigint,
    )
    deadline = time.monotonic() + 120
    workers = []
    while time.monotonic() < deadline and len(workers) < 2:  # the pool is up
        time.sleep(0.2)
        workers = [w for w in _children(child.pid) if _alive(w)]
    if ready is None:
        time.sleep(wait)  # some points done
    while ready is not None and time.monotonic() < deadline + 120 and not ready():
        time.sleep(0.1)
    sent = time.monotonic()
    child.send_signal(signum)
    _, err = child.communicate(timeout=30)
    elapsed = time.monotonic() - sent
    time.sleep(0.5)
    return child.returncode, err, elapsed, workers


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="reads worker processes from Linux's /proc")
@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
@pytest.mark.parametrize(
    "arguments, table, cells, column",
    [
        (REGIMES, "regimes.csv", 36, "regime"),
        pytest.param(TRUST, "trust_map.csv", 12, "status", marks=pytest.mark.slow),
    ],
    ids=["regimes", "trust"],
)
def test_a_stopped_map_keeps_what_it_did_and_leaves_no_worker(
    tmp_path, signum, code, arguments, table, cells, column
):
    out = tmp_path / "map"
    returncode, err, elapsed, workers = _stop_while_running(arguments, signum, out)
    assert returncode == code, err
    assert elapsed < 10  # within 2 s of work, plus writing the files on a busy machine
    assert workers and not any(_alive(w) for w in workers)
    assert "interrupted" in err and "Traceback" not in err
    with open(out / table, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == cells
    assert any(r[column].startswith("not computed") for r in rows)
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]  # no partial file left


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="reads worker processes from Linux's /proc")
@pytest.mark.parametrize(
    "grid, store, table, cells",
    [
        pytest.param(
            # long enough (about 12 s on a fast machine) for the partial file (every 5 s) to hold a cell
            ["regimes", "--preset", "fig13", "--sigma-points", "8", "--abar-points", "8", "--tmax", "3000"],
            "regimes.json",
            "regimes.csv",
            64,
            marks=pytest.mark.slow,  # the default run resumes from a partial store, no signal (below)
        ),
        pytest.param(
            ["basins", "--preset", "fig10", "--set", "sigma=3", "--grid", "16", "16", "--tmax", "12000"],
            "basins.json",
            "basins.csv",
            256,
            marks=pytest.mark.slow,
        ),
    ],
    ids=["regimes", "basins"],
)
def test_an_interrupted_map_resumed_equals_an_uninterrupted_one(tmp_path, capsys, grid, store, table, cells):
    import json

    from slosh_bif.cli import main

    def stored(name):
        try:
            return len(json.loads((tmp_path / "a" / name).read_text())["cells"])
        except (OSError, ValueError, KeyError):  # not written yet
            return 0

    # the running map rewrites <stem>.partial.json every 5 s: signal once it holds a cell
    partial = store.replace(".json", ".partial.json")
    returncode, err, _, _ = _stop_while_running(
        grid, signal.SIGINT, tmp_path / "a", ready=lambda: stored(partial) > 0
    )
    assert returncode == 130, err
    kept = stored(store)
    assert 0 < kept < cells
    assert main([*grid, "--workers", "2", "--resume", "--out", str(tmp_path / "a")]) == 0
    assert f"resuming: {kept} of {cells}" in capsys.readouterr().err
    assert main([*grid, "--workers", "2", "--out", str(tmp_path / "b")]) == 0
    assert (tmp_path / "a" / table).read_text() == (tmp_path / "b" / table).read_text()
    # other settings: refused in one line, before any work
    assert main([*grid[:-1], "2000", "--resume", "--out", str(tmp_path / "a")]) == 2
    assert "tmax differ" in capsys.readouterr().err


def test_a_map_resumed_from_a_partial_store_equals_an_uninterrupted_one(tmp_path, capsys):
    """What an interrupted run leaves (``regimes.partial.json``, part of the cells), taken from a
    real run's store: ``--resume`` simulates only the rest, and the files equal an uninterrupted
    run's."""
    import json

    from slosh_bif.cli import main

    grid = ["regimes", "--preset", "fig13", "--sigma-points", "4", "--abar-points", "3", "--tmax", "1500"]
    assert main([*grid, "--workers", "2", "--out", str(tmp_path / "b")]) == 0
    store = json.loads((tmp_path / "b" / "regimes.json").read_text())
    kept = dict(list(store["cells"].items())[::2])  # every other cell, as a stop part way leaves them
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "regimes.partial.json").write_text(
        json.dumps({**store, "status": "running", "cells": kept}) + "\n"
    )
    capsys.readouterr()
    assert main([*grid, "--workers", "2", "--resume", "--out", str(tmp_path / "a")]) == 0
    assert f"resuming: {len(kept)} of 12" in capsys.readouterr().err
    assert not (tmp_path / "a" / "regimes.partial.json").exists()
    assert (tmp_path / "a" / "regimes.csv").read_text() == (tmp_path / "b" / "regimes.csv").read_text()


@pytest.mark.slow  # resuming from a partial store: the test above covers it in the default run
def test_a_killed_map_resumes_from_the_cells_stored_on_the_way(tmp_path, capsys):
    """SIGKILL (no handler runs): the partial store written every few seconds as cells finish is
    what a resumed run reuses, and the folder's previous complete results are untouched."""
    import json

    from slosh_bif.cli import main
    from slosh_bif.report import files

    # ~20 s of work on 2 cores with a warm compilation cache (tmax 3000 finished in 8.6 s, before the kill)
    grid = ["regimes", "--preset", "fig13", "--sigma-points", "6", "--abar-points", "6", "--tmax", "8000"]
    returncode, err, _, workers = _stop_while_running(
        grid, signal.SIGKILL, tmp_path / "a", wait=8.0
    )  # past the first store, 5 s in
    assert returncode == -signal.SIGKILL
    time.sleep(1.0)
    assert workers and not any(
        _alive(w) for w in workers
    )  # they end with their parent (a watch on it in each worker)
    assert not (tmp_path / "a" / "regimes.json").exists()  # never completed: no result file claims to be one
    kept = len(json.loads((tmp_path / "a" / "regimes.partial.json").read_text())["cells"])
    assert 0 < kept < 36
    assert main([*grid, "--workers", "2", "--resume", "--out", str(tmp_path / "a")]) == 0
    assert f"resuming: {kept} of 36" in capsys.readouterr().err
    assert not (tmp_path / "a" / "regimes.partial.json").exists()
    assert (
        files.read_store(
            tmp_path / "a" / "regimes.json",
            json.loads((tmp_path / "a" / "regimes.json").read_text())["settings"],
        )["status"]
        == "complete"
    )


CHART = [
    "chart",
    "--preset",
    "fig10",
    "--sigma-min",
    "-6",
    "--sigma-max",
    "8",
    "--abar-min",
    "0.2",
    "--abar-max",
    "6",
    "--no-switch",
]


@pytest.mark.slow  # stopping with workers: the maps' tests cover it in the default run
@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="reads worker processes from Linux's /proc")
def test_a_stopped_chart_keeps_its_finished_curves_and_leaves_no_worker(tmp_path):
    out = tmp_path / "chart"
    returncode, err, elapsed, workers = _stop_while_running(CHART, signal.SIGINT, out)
    assert returncode == 130, err
    assert elapsed < 10 and workers and not any(_alive(w) for w in workers)
    assert "interrupted" in err and "Traceback" not in err
    stored = sorted((out / "curves").glob("curve-*.npz"))
    with open(out / "curves.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert not (out / "critical.csv").exists()  # read off every curve or not at all
    assert stored and 0 < len({r["curve"] for r in rows}) <= len(
        stored
    )  # the finished curves (one of two duplicates dropped), complete


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="reads worker processes from Linux's /proc")
def test_a_chart_stopped_while_its_regime_map_runs_beside_the_family_leaves_no_worker(tmp_path):
    # the map's cells start on the shared pool before the orbit family is traced in this process:
    # a Ctrl-C then (no curve yet) kills the pool's workers and exits 130
    out = tmp_path / "chart"
    arguments = [*CHART, "--regimes", "6", "6", "--tmax", "3000"]
    returncode, err, elapsed, workers = _stop_while_running(arguments, signal.SIGINT, out, wait=1.0)
    assert returncode == 130, err
    assert elapsed < 10 and len(workers) == 2 and not any(_alive(w) for w in workers)
    assert "Traceback" not in err and not (out / "curves.csv").exists()


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_the_critical_forcing_of_the_full_model_stops_on_a_signal(signum, code):
    """``answer critical-forcing`` traces curves in process (as the bench's critical-forcing step
    does): a signal while a curve is traced stops the command, it does not end that curve's
    stage early and go on with a partial answer."""
    child = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "slosh_bif.cli",
            "answer",
            "critical-forcing",
            "--preset",
            "fig13",
            "--tol",
            "0.3",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=default_sigint,
    )
    for line in child.stderr:  # the curves are being traced
        if "curve from" in line or "special points" in line:
            break
    sent = time.monotonic()
    child.send_signal(signum)
    _, err = child.communicate(timeout=60)
    assert child.returncode == code, err
    assert time.monotonic() - sent < 10  # within 2 s of work, on a busy machine
    assert "Traceback" not in err


def test_an_interrupt_inside_numbas_loading_ends_as_an_interrupt(monkeypatch, capsys):
    # Ctrl-C while numba unpickles cached code for a compiled loop's first call surfaces as a
    # SystemError (the loop's dispatcher) caused by a SystemError (numba's unpickler) caused by
    # the KeyboardInterrupt (seen in CI on a cold cache): the command still ends with status 130.
    from slosh_bif.cli import info, main

    def interrupted_inside_numba(args):
        try:
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as stop:
                raise SystemError(
                    "<function _numba_unpickle> returned a result with an exception set"
                ) from stop
        except SystemError as inner:
            raise SystemError("CPUDispatcher(_arcs_loop) returned a result with an exception set") from inner

    monkeypatch.setattr(info, "params_of", interrupted_inside_numba)
    assert main(["info", "--preset", "fig10"]) == 130
    assert "Traceback" not in capsys.readouterr().err
