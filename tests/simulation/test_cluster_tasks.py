"""A task sent to a cluster holds its worker's BLAS to one thread, as a local worker's is
(:class:`slosh_bif.simulation.sweep.OneBlasThread`): checked in a fresh interpreter whose BLAS
was given two threads, as a ``dask worker`` started from a plain shell on a 2-core machine has."""

import json
import os
import subprocess
import sys

import pytest

_TASK = """
import json
from threadpoolctl import threadpool_info, threadpool_limits

def blas_threads():
    return sorted({d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"})

import numpy
threadpool_limits(limits=2, user_api="blas")
before = blas_threads()
from slosh_bif.simulation.sweep import OneBlasThread
task = OneBlasThread(blas_threads)
print(json.dumps([before, task(), blas_threads(), task.__name__]))
"""


def test_a_cluster_task_runs_with_one_blas_thread_and_leaves_it_so():
    limits = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS")
    env = {k: v for k, v in os.environ.items() if k not in limits}
    done = subprocess.run([sys.executable, "-c", _TASK], capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    before, during, after, name = json.loads(done.stdout.strip().splitlines()[-1])
    assert name == "blas_threads"  # a cluster's task keys show the function's name
    if before != [2]:
        pytest.skip(f"this machine's BLAS does not take two threads (it reports {before})")
    assert during == [1] and after == [1]
