"""Interruption (issue 18): a regime map stopped by SIGINT or SIGTERM exits within seconds with
130 / 143, leaves no worker process behind, and writes the points it finished, the rest marked
"not computed", in complete files."""

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


@pytest.mark.skipif(not os.path.exists("/proc/self/task"), reason="reads worker processes from Linux's /proc")
@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_stopped_regime_map_keeps_what_it_did_and_leaves_no_worker(tmp_path, signum, code):
    out = tmp_path / "map"
    command = [sys.executable, "-m", "slosh_bif.cli", "regimes", "--preset", "fig13", "--sigma-points", "6", "--abar-points", "6",
               "--tmax", "3000", "--workers", "2", "--out", str(out)]
    child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    workers = []
    while time.monotonic() < deadline and len(workers) < 2:  # the pool is up
        time.sleep(0.2)
        workers = [w for w in _children(child.pid) if _alive(w)]
    time.sleep(3.0)  # some points done
    sent = time.monotonic()
    child.send_signal(signum)
    _, err = child.communicate(timeout=30)
    assert child.returncode == code, err
    assert time.monotonic() - sent < 10  # within 2 s of work, plus writing the files on a busy machine
    time.sleep(0.5)
    assert workers and not any(_alive(w) for w in workers)
    assert "interrupted" in err and "Traceback" not in err
    with open(out / "regimes.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 36
    assert any(r["regime"] == "not computed" for r in rows)
    assert sorted(p.name for p in out.iterdir()) == ["regimes.csv", "regimes.png"]
