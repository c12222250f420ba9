"""A chart on a dask cluster started as processes, as a user starts one (``dask scheduler``,
``dask worker``): the same files, byte for byte, as the local run, also when a worker is killed
while it traces a curve (the scheduler runs its task again on the other worker); and the task
durations it records."""

import csv
import os
import signal
import subprocess
import sys

import pytest

from slosh_bif.cli import main
from slosh_bif.report.tasks import Task, projected_seconds

FILES = ("curves.csv", "codim2.csv")


def test_a_chart_on_a_cluster_of_processes_survives_a_killed_worker(
    tmp_path, cluster, beta_chart, cluster_environment, wait_for
):
    address, client, workers = cluster
    run = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "slosh_bif",
            *beta_chart,
            "--scheduler",
            address,
            "--out",
            str(tmp_path / "dask"),
        ],
        env=cluster_environment,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    # the first worker seen tracing a curve is killed while it does
    busy = wait_for(lambda: [w for w, keys in client.processing().items() if keys], 120, "curve task")
    pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
    workers[pid].send_signal(signal.SIGKILL)
    out, err = run.communicate(timeout=300)
    assert run.returncode == 0, err
    assert len(client.scheduler_info()["workers"]) == 1  # the killed one is gone
    assert main([*beta_chart, "--workers", "1", "--out", str(tmp_path / "local")]) == 0
    for name in FILES:
        assert (tmp_path / "dask" / name).read_text() == (tmp_path / "local" / name).read_text(), name
    tasks, rows = (
        list(csv.DictReader((tmp_path / "dask" / name).read_text().splitlines()))
        for name in ("tasks.csv", "curves.csv")
    )
    curves = {int(row["curve"]) for row in rows}
    assert len(tasks) >= len(curves) and all(float(t["seconds"]) > 0 for t in tasks)
    assert "projected on 1, 2, 8, 32, 128 workers" in out


def test_the_projection_is_list_scheduling_in_start_order():
    tasks = [Task(i, "LP", "x", s, 10) for i, s in enumerate((4.0, 1.0, 1.0, 1.0, 3.0))]
    assert projected_seconds(tasks, 1) == pytest.approx(10.0)
    # two workers: 4 | 1, 1, 1, then 3 to the second (free at 3): 6
    assert projected_seconds(tasks, 2) == pytest.approx(6.0)
    assert projected_seconds(tasks, 128) == pytest.approx(4.0)  # the longest bounds it
    with pytest.raises(ValueError, match="workers must be >= 1"):
        projected_seconds(tasks, 0)
