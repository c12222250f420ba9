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
TRUST = ["trust", "--preset", "fig13", "--no-switch", "--eps", "0.02,0.05,0.1", "--beta", "0,0.3", "--n", "20,50"]


def _stop_while_running(arguments, signum, out):
    child = subprocess.Popen([sys.executable, "-m", "slosh_bif.cli", *arguments, "--workers", "2", "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    workers = []
    while time.monotonic() < deadline and len(workers) < 2:  # the pool is up
        time.sleep(0.2)
        workers = [w for w in _children(child.pid) if _alive(w)]
    time.sleep(4.0)  # some points done
    sent = time.monotonic()
    child.send_signal(signum)
    _, err = child.communicate(timeout=30)
    elapsed = time.monotonic() - sent
    time.sleep(0.5)
    return child.returncode, err, elapsed, workers


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="reads worker processes from Linux's /proc")
@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
@pytest.mark.parametrize("arguments, table, cells, column", [(REGIMES, "regimes.csv", 36, "regime"), (TRUST, "trust_map.csv", 12, "status")], ids=["regimes", "trust"])
def test_a_stopped_map_keeps_what_it_did_and_leaves_no_worker(tmp_path, signum, code, arguments, table, cells, column):
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
def test_an_interrupted_map_resumed_equals_an_uninterrupted_one(tmp_path, capsys):
    import json

    from slosh_bif.cli import main

    grid = ["regimes", "--preset", "fig13", "--sigma-points", "5", "--abar-points", "5", "--tmax", "3000"]
    returncode, err, _, _ = _stop_while_running(grid, signal.SIGINT, tmp_path / "a")
    assert returncode == 130, err
    kept = len(json.loads((tmp_path / "a" / "regimes.json").read_text())["cells"])
    assert 0 < kept < 25
    assert main([*grid, "--workers", "2", "--resume", "--out", str(tmp_path / "a")]) == 0
    assert f"resuming: {kept} of 25" in capsys.readouterr().err
    assert main([*grid, "--workers", "2", "--out", str(tmp_path / "b")]) == 0
    assert (tmp_path / "a" / "regimes.csv").read_text() == (tmp_path / "b" / "regimes.csv").read_text()
    # other settings: refused in one line, before any work
    assert main([*grid[:-1], "2000", "--resume", "--out", str(tmp_path / "a")]) == 2
    assert "tmax differ" in capsys.readouterr().err


CHART = ["chart", "--preset", "fig10", "--sigma-min", "-6", "--sigma-max", "8", "--abar-min", "0.2", "--abar-max", "6", "--no-switch"]


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
    assert stored and 0 < len({r["curve"] for r in rows}) <= len(stored)  # the finished curves (one of two duplicates dropped), complete
