"""Running the cells of a sweep (a regime map, a basin map) through an executor.

Every cell is an independent simulation, so any ``concurrent.futures.Executor`` can run them: a
local ``ProcessPoolExecutor`` (the default, one worker per core, each with one BLAS thread), or a
Dask cluster's ``distributed.Client(address).get_executor()`` (the CLI's ``--scheduler``, through
:class:`ClusterExecutor`, whose tasks hold their worker's BLAS to one thread as well). Results
are handed to the caller as they finish, so that a long sweep can store them on the way; an
interruption (KeyboardInterrupt, or SIGTERM turned into one by the CLI) stops the local workers at
once, cancels what a cluster has not started, and returns what was done.
"""

from __future__ import annotations

import contextlib
from concurrent.futures import ProcessPoolExecutor, as_completed

from slosh_bif.report.files import Resume
from slosh_bif.simulation.settings import LOCAL, Workers

__all__ = [
    "WorkerPool",
    "ClusterExecutor",
    "OneBlasThread",
    "PendingCells",
    "local_pool",
    "run_cells",
    "submit_cells",
    "worker_setup",
]


def worker_setup(pids=None) -> None:
    """Initializer of every worker process: one BLAS thread (the matrices here are tiny, and a
    busy machine makes OpenBLAS's threads cost 300x), Ctrl-C and SIGTERM left to the parent,
    which stops the workers itself (a terminal's SIGINT reaches the whole process group, and
    each worker would print a traceback), and a watch on the parent. ``pids``: a queue on which
    the worker announces its process id, so that its pool can kill it."""
    import os
    import signal

    from threadpoolctl import threadpool_limits

    if pids is not None:
        pids.put(os.getpid())
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _exit_with_parent(os.getppid())
    threadpool_limits(limits=1, user_api="blas")


def _exit_with_parent(parent: int, every: float = 0.2) -> None:
    """A daemon thread that ends this worker when its parent is gone (the worker is then adopted
    and its parent id changes): a parent killed by SIGKILL or the OOM killer runs no handler that
    could stop its workers. The compiled code releases the GIL, so the watch runs during it."""
    import os
    import threading
    import time

    def watch():
        while os.getppid() == parent:
            time.sleep(every)
        os._exit(1)

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


class WorkerPool:
    """Local worker processes (``max_workers``, one per core by default) that can be stopped at
    once: a ``ProcessPoolExecutor`` whose workers announce their process ids, since a simulation in
    a worker cannot be interrupted any other way than by killing it."""

    place = "local processes"  # where its tasks run, for progress lines

    def __init__(self, max_workers: int | None = None):
        import multiprocessing

        self._pids = multiprocessing.get_context().SimpleQueue()
        self.threads = max_workers or multiprocessing.cpu_count()  # tasks at once
        self.executor = ProcessPoolExecutor(
            max_workers=max_workers, initializer=worker_setup, initargs=(self._pids,)
        )

    def submit(self, function, *arguments):
        return self.executor.submit(function, *arguments)

    def close(self) -> None:
        """Wait for the submitted work, then end the workers."""
        self.executor.shutdown()

    def stop(self) -> None:
        """Cancel what has not started and kill the workers now."""
        import os
        import signal

        self.executor.shutdown(wait=False, cancel_futures=True)
        while not self._pids.empty():
            try:
                os.kill(self._pids.get(), signal.SIGKILL)
            except ProcessLookupError:  # already ended
                pass


@contextlib.contextmanager
def local_pool(workers: int):
    """Local worker processes for ``workers`` above 1 (stopped at once when the block is left by an
    exception: Ctrl-C, SIGTERM; else closed once their work is done), or None (this process)."""
    if workers <= 1:
        yield None
        return
    pool = WorkerPool(workers)
    try:
        yield pool
    except BaseException:
        pool.stop()
        raise
    pool.close()


class OneBlasThread:
    """``OneBlasThread(function)(*arguments)``: ``function(*arguments)`` with this process's BLAS held
    to one thread, as :func:`worker_setup` holds a local worker's. What a task sent to a cluster
    runs, since a worker started by ``dask worker`` lets OpenBLAS start a thread per core on the
    4x4 to 32x32 matrices here, where threads only cost (a Fig. 13 chart of (8) on two such workers
    of a 2-core machine: 69.9 s of curve work against 13.2 s with one BLAS thread each). scipy's
    own BLAS is loaded first, so that the limit reaches it; the limit stays for the worker's later
    tasks (0.4 ms a call). Named as ``function``, which a cluster's task keys and dashboard show."""

    def __init__(self, function):
        self.function = function
        self.__name__ = getattr(function, "__name__", type(function).__name__)

    def __call__(self, *arguments):
        import scipy.linalg  # noqa: F401 - loads scipy's BLAS, which would otherwise load unlimited later
        from threadpoolctl import threadpool_limits

        threadpool_limits(limits=1, user_api="blas")
        return self.function(*arguments)


class ClusterExecutor:
    """A dask cluster's executor (``distributed.Client.get_executor()``) with the cluster's thread
    count when it was reached: how many tasks a caller that keeps a bounded number in flight (a
    chart's curves, each skipped when an earlier one covers it) submits at once. Each task runs
    with one BLAS thread (:class:`OneBlasThread`). A worker lost mid-task is dask's to handle: the
    scheduler runs the task again on another."""

    place = "the cluster"

    def __init__(self, client):
        self.executor = client.get_executor()
        self.threads = max(1, sum(client.nthreads().values()))

    def submit(self, function, *arguments):
        return self.executor.submit(OneBlasThread(function), *arguments)


def run_cells(
    function,
    jobs: dict,
    *,
    workers: Workers = LOCAL,
    resume: Resume | None = None,
    progress=None,
    total: int | None = None,
):
    """``function(*arguments)`` for every ``key: arguments`` of ``jobs`` not already in
    ``resume.done``, on ``workers``.

    Returns ``(results, status)``: {key: result} (``resume.done``'s included) and "complete", or
    "interrupted (SIGNAL) after k of n points". ``progress(count, total)`` and
    ``resume.keep(key, result)`` are called as cells finish, in the order they finish.
    """
    return submit_cells(function, jobs, workers=workers, resume=resume, total=total).collect(progress)


def submit_cells(
    function, jobs: dict, *, workers: Workers = LOCAL, resume: Resume | None = None, total: int | None = None
):
    """The cells of :func:`run_cells` submitted now and collected later (:class:`PendingCells`),
    so that other work can share the executor meanwhile (a chart's curves beside its regime map)."""
    return PendingCells(function, jobs, workers, resume or Resume(), total)


class PendingCells:
    """Cells submitted to their executor: :meth:`collect` waits for them (as :func:`run_cells`
    does), :meth:`cancel` drops them (local workers stopped at once, a cluster's unstarted tasks
    cancelled)."""

    def __init__(self, function, jobs: dict, workers: Workers, resume: Resume, total: int | None):
        self.keep = resume.keep
        self.results = dict(resume.done or {})
        self.total = len(jobs) if total is None else total
        todo = {key: arguments for key, arguments in jobs.items() if key not in self.results}
        self.local = WorkerPool(workers.max_workers) if workers.executor is None else None
        pool = self.local.executor if self.local is not None else workers.executor
        self.futures = {}
        try:
            for key, arguments in todo.items():
                self.futures[pool.submit(function, *arguments)] = key
        except BaseException:
            self.cancel()
            raise

    def collect(self, progress=None):
        """``(results, status)`` as :func:`run_cells` returns them, once every cell has finished
        or an interruption stopped them."""
        status = "complete"
        try:
            for count, future in enumerate(as_completed(self.futures), len(self.results) + 1):
                key = self.futures[future]
                self.results[key] = future.result()
                if self.keep is not None:
                    self.keep(key, self.results[key])
                if progress is not None:
                    progress(count, self.total)
        except KeyboardInterrupt as stop:
            status = (
                f"interrupted ({getattr(stop, 'signal_name', 'SIGINT')}) after {len(self.results)} of "
                f"{self.total} points"
            )
            self.cancel()
        finally:
            if self.local is not None and status == "complete":
                self.local.close()
        return self.results, status

    def cancel(self) -> None:
        """Stop the cells that have not finished: the local workers killed, a cluster's tasks cancelled."""
        if self.local is not None:
            self.local.stop()
        else:
            for future in self.futures:
                future.cancel()
