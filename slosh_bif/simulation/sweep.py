"""Running the cells of a sweep (a regime map, a basin map) through an executor.

Every cell is an independent simulation, so any ``concurrent.futures.Executor`` can run them: a
local ``ProcessPoolExecutor`` (the default, one worker per core, each with one BLAS thread), or a
Dask cluster's ``distributed.Client(address).get_executor()`` (the CLI's ``--scheduler``). Results
are handed to the caller as they finish, so that a long sweep can store them on the way; an
interruption (KeyboardInterrupt, or SIGTERM turned into one by the CLI) stops the local workers at
once, cancels what a cluster has not started, and returns what was done.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor, as_completed

__all__ = ["run_cells", "worker_setup", "stop_pool"]


def worker_setup() -> None:
    """Initializer of every worker process: one BLAS thread (the matrices here are tiny, and a
    busy machine makes OpenBLAS's threads cost 300x), and Ctrl-C and SIGTERM left to the parent,
    which stops the workers itself (a terminal's SIGINT reaches the whole process group, and
    each worker would print a traceback)."""
    import signal

    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _die_with_parent()


def _die_with_parent() -> None:
    """On Linux, ask the kernel to kill this worker when its parent dies: a parent killed by
    SIGKILL (or the OOM killer) runs no handler that could stop its workers."""
    import ctypes
    import signal
    import sys

    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG = 1
        except OSError:
            pass


def stop_pool(pool) -> None:
    """Cancel what has not started and kill the workers of a ``ProcessPoolExecutor`` at once (a
    simulation in a worker cannot be interrupted any other way)."""
    processes = list(getattr(pool, "_processes", {}).values())  # the executor keeps no public handle on them
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.kill()
    for process in processes:
        process.join(timeout=2.0)


def run_cells(function, jobs: dict, *, executor=None, max_workers: int | None = None, progress=None, done=None, on_result=None, total: int | None = None):
    """``function(*arguments)`` for every ``key: arguments`` of ``jobs`` not already in ``done``.

    Returns ``(results, status)``: {key: result} (``done``'s included) and "complete", or
    "interrupted (SIGNAL) after k of n points". ``progress(count, total)`` and
    ``on_result(key, result)`` are called as cells finish, in the order they finish.
    """
    results = dict(done or {})
    total = len(jobs) if total is None else total
    todo = {key: arguments for key, arguments in jobs.items() if key not in results}
    own = executor is None
    pool = ProcessPoolExecutor(max_workers=max_workers, initializer=worker_setup) if own else executor
    status, futures = "complete", {}
    try:
        futures = {pool.submit(function, *arguments): key for key, arguments in todo.items()}
        for count, future in enumerate(as_completed(futures), len(results) + 1):
            key = futures[future]
            results[key] = future.result()
            if on_result is not None:
                on_result(key, results[key])
            if progress is not None:
                progress(count, total)
    except KeyboardInterrupt as stop:
        status = f"interrupted ({getattr(stop, 'signal_name', 'SIGINT')}) after {len(results)} of {total} points"
        if own:
            stop_pool(pool)
        else:
            for future in futures:
                future.cancel()
    finally:
        if own and status == "complete":
            pool.shutdown()
    return results, status
