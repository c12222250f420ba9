"""``shoot --start scan`` side by side on a dask cluster started as processes, a worker killed while
it traces a family: the files are those of the sequential scan, byte for byte (the families traced
ahead of their turn are checked against the branches known when their turn comes, and renamed as
the sequential scan names them). The API's side-by-side scan on a thread pool: the sequential
branches."""

import os
import signal
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from slosh_bif.cli import main

# Two families at sigma = 1 of the Fig. 10 set, found from two random states: the second has a
# switched branch whose origin names its parent, so a family traced ahead is renamed.
SCAN = [
    "shoot",
    "--preset",
    "fig10",
    "--start",
    "scan",
    "--scan-points",
    "1",
    "--scan-random",
    "2",
    "--max-branches",
    "2",
    "--sigma-min",
    "-1",
    "--sigma-max",
    "3",
]
FILES = ("branch.csv", "families.csv")


def _same_files(a, b):
    for name in FILES:
        assert (a / name).read_text() == (b / name).read_text(), name


@pytest.mark.slow  # 50 s: the fast check is the thread pool's below
def test_a_scan_on_a_cluster_of_processes_survives_a_killed_worker(
    tmp_path, cluster, cluster_environment, wait_for
):
    address, client, workers = cluster
    run = subprocess.Popen(
        [sys.executable, "-m", "slosh_bif", *SCAN, "--scheduler", address, "--out", str(tmp_path / "dask")],
        env=cluster_environment,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    busy = wait_for(
        lambda: [w for w, keys in client.processing().items() if any("family_task" in k for k in keys)],
        180,
        "family task",
    )
    pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
    workers[pid].send_signal(signal.SIGKILL)
    _, err = run.communicate(timeout=600)
    assert run.returncode == 0, err
    assert len(client.scheduler_info()["workers"]) == 1  # the killed one is gone
    assert err.count("scan: a new family") >= 2
    assert main([*SCAN, "--workers", "1", "--out", str(tmp_path / "one")]) == 0
    _same_files(tmp_path / "dask", tmp_path / "one")


class _Threads(ThreadPoolExecutor):
    threads = 2


def test_the_side_by_side_scan_gives_the_sequential_branches(monkeypatch):
    """The API's scan on a thread pool gives the sequential branches, and while the family whose
    turn it is runs on a worker a line every HEARTBEAT seconds says so."""
    from slosh_bif import get_preset
    from slosh_bif.orbits import scan_pool
    from slosh_bif.orbits.scan import scan_families
    from slosh_bif.orbits.settings import BranchingSettings, ParameterRange, StartSettings

    monkeypatch.setattr(scan_pool, "HEARTBEAT", 0.2)
    preset = get_preset("fig10")
    settings = dict(
        interval=ParameterRange(lo=0.6, hi=1.5),
        starts=StartSettings(points=1, random_starts=2, settle=150),
        branching=BranchingSettings(max_branches=1),
    )
    alone = scan_families(preset.params, preset.state_for(preset.params), **settings)
    with _Threads(2) as pool:
        said = []
        beside = scan_families(
            preset.params, preset.state_for(preset.params), executor=pool, progress=said.append, **settings
        )
    assert any("is being traced on a worker (" in line for line in said)
    assert len(alone.branches) >= 2
    assert [(ob.name, ob.origin, ob.found_from) for ob in beside.branches] == [
        (ob.name, ob.origin, ob.found_from) for ob in alone.branches
    ]
    for a, b in zip(alone.branches, beside.branches):
        assert np.array_equal(a.branch.x, b.branch.x) and np.array_equal(a.branch.p, b.branch.p)
    # both record the same tasks (each start job, each family traced), in the order they were dealt with
    assert sorted((t.kind, t.origin, t.points) for t in beside.tasks) == sorted(
        (t.kind, t.origin, t.points) for t in alone.tasks
    )
    assert {t.kind for t in alone.tasks} == {"start", "family"}
    assert [t.start for t in alone.tasks] == list(range(len(alone.tasks)))
    assert all(t.seconds > 0 for t in alone.tasks + beside.tasks)
