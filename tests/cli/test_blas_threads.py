"""One BLAS thread in every process the command line starts, whatever loads BLAS later."""

import json
import os
import subprocess
import sys

PROBE = """
import json
import slosh_bif.cli  # what the slosh-bif entry point imports first
import numpy, scipy.linalg
scipy.linalg.expm(numpy.eye(4))  # scipy's own OpenBLAS loads here, after the command line set up
from concurrent.futures import ProcessPoolExecutor
from slosh_bif.simulation.sweep import worker_setup
from threadpoolctl import threadpool_info

def blas():
    import numpy, scipy.linalg
    scipy.linalg.expm(numpy.eye(4))
    return [d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"]

if __name__ == "__main__":
    with ProcessPoolExecutor(1, initializer=worker_setup) as pool:
        worker = pool.submit(blas).result()
    print(json.dumps({"main": blas(), "worker": worker}))
"""


def test_one_blas_thread_after_scipy_linalg_loads_in_the_command_and_its_workers(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    out = subprocess.run(
        [sys.executable, str(script)], env=env, capture_output=True, text=True, timeout=120, check=True
    ).stdout
    threads = json.loads(out)
    assert threads["main"] and threads["worker"]
    assert set(threads["main"]) == {1} and set(threads["worker"]) == {1}
