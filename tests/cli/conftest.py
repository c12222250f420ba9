"""Shared by the command tests: a dask cluster started as processes, as a user starts one
(``dask scheduler``, ``dask worker``)."""

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import distributed  # in the test extra
import pytest

import slosh_bif


def _environment() -> dict:
    """The workers import the package the test imports (a checkout or the installed one)."""
    root = str(Path(slosh_bif.__file__).resolve().parents[1])
    return os.environ | {"PYTHONPATH": os.pathsep.join(filter(None, (root, os.environ.get("PYTHONPATH"))))}


def _wait_for(condition, seconds: float, what: str):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"no {what} within {seconds} s")


@pytest.fixture
def cluster(tmp_path):
    """A scheduler and two single-threaded workers (no nanny: a killed worker stays dead), each
    its own process; all ended after the test."""
    file = tmp_path / "scheduler.json"
    env = _environment()
    command = [sys.executable, "-m", "distributed.cli.dask_scheduler", "--port", "0", "--no-dashboard"]
    processes = [
        subprocess.Popen([*command, "--scheduler-file", str(file)], env=env, stderr=subprocess.DEVNULL)
    ]
    try:
        _wait_for(file.exists, 60, "scheduler file")
        address = _wait_for(lambda: json.loads(file.read_text() or "{}").get("address"), 60, "address")
        worker = [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1"]
        worker += ["--no-nanny", "--no-dashboard"]
        processes += [subprocess.Popen(worker, env=env, stderr=subprocess.DEVNULL) for _ in range(2)]
        with distributed.Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
            yield address, client, {p.pid: p for p in processes[1:]}
    finally:
        for p in processes:
            p.kill()
            p.wait()


@pytest.fixture
def cluster_environment() -> dict:
    """The environment of a process that runs on the cluster's package (a checkout's or the installed)."""
    return _environment()


@pytest.fixture
def wait_for():
    """``wait_for(condition, seconds, what)``: condition()'s first true value, polled; fails after
    ``seconds``."""
    return _wait_for
