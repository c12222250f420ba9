"""A task sent to a cluster holds its worker's BLAS to one thread, as a local worker's is
(:class:`slosh_bif.simulation.sweep.OneBlasThread`): the limit is set, on every BLAS, before the
task's function runs, and a fresh interpreter given more threads reads one inside the task."""

import json
import os
import subprocess
import sys

_TASK = """
import json
from threadpoolctl import threadpool_info, threadpool_limits

def blas_threads():
    return sorted({d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"})

import numpy
threadpool_limits(limits=2, user_api="blas")  # a dask worker's BLAS on a machine of two or more cores
from slosh_bif.simulation.sweep import OneBlasThread
task = OneBlasThread(blas_threads)
print(json.dumps([task(), blas_threads(), task.__name__]))
"""


def test_a_cluster_task_limits_blas_before_its_function_runs(monkeypatch):
    import threadpoolctl

    from slosh_bif.simulation.sweep import OneBlasThread

    calls = []
    monkeypatch.setattr(threadpoolctl, "threadpool_limits", lambda **kw: calls.append(("limit", kw)))

    def work(a, b):
        calls.append(("work", a + b, "scipy.linalg" in sys.modules))
        return a * b

    assert OneBlasThread(work)(3, 4) == 12
    assert calls == [("limit", {"limits": 1, "user_api": "blas"}), ("work", 7, True)]


def test_a_cluster_task_runs_with_one_blas_thread_in_a_fresh_interpreter_and_leaves_it_so():
    limits = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS")
    env = {k: v for k, v in os.environ.items() if k not in limits}
    done = subprocess.run([sys.executable, "-c", _TASK], capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    during, after, name = json.loads(done.stdout.strip().splitlines()[-1])
    assert during == [1] and after == [1]
    assert name == "blas_threads"  # a cluster's task keys show the function's name
