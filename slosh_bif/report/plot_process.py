"""A figure drawn by a forked process that imports matplotlib while the command computes.

matplotlib's import (about 0.4 s, most of it building the artists' property docs) is a fifth of a
whole ``shoot`` run of the Fig. 10 set; on a machine with a second core a process forked at the
command's start imports it while the parent traces the branch, then draws the figure it is sent.
Where no fork is safe (no ``os.fork``, or threads already running: a forked child holds only the
forking thread, and a lock another thread held would never be released) the figure is drawn in
the calling process, as it would be without this module.
"""

from __future__ import annotations

import os
import pickle
import signal
import sys
import threading

__all__ = ["PlotProcess"]


def _can_fork() -> bool:
    return hasattr(os, "fork") and threading.active_count() == 1


class PlotProcess:
    """``with PlotProcess() as plots: ...; plots.submit(plot_family, family, path); ...; path =
    plots.result()``: the child (when there is one) imports matplotlib at once and runs the one
    call it is sent; its value, or its exception, comes back as the call's own. Leaving the block
    without a result ends the child."""

    def __init__(self):
        self._pid, self._jobs, self._call = None, None, None
        if not _can_fork():
            return
        sys.stdout.flush()  # the child inherits unflushed buffers: nothing may be written twice
        sys.stderr.flush()
        jobs, self._jobs = os.pipe()
        self._results, results = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: never returns
            os.close(self._jobs)
            os.close(self._results)
            _child(jobs, results)
        os.close(jobs)
        os.close(results)
        self._pid = pid

    def submit(self, function, *args, **kwargs) -> None:
        """Send ``function(*args, **kwargs)`` to the child (keep it, to run in :meth:`result`,
        where there is none, or where the call cannot be sent: it does not pickle, or the child
        is gone); the caller goes on while it draws."""
        self._call = (function, args, kwargs)
        if self._pid is None:
            return
        try:
            job = pickle.dumps(self._call, protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:  # not picklable: drawn in this process
            self.close()
            return
        fd, self._jobs = self._jobs, None
        try:
            with os.fdopen(fd, "wb") as jobs:
                jobs.write(job)
        except OSError:  # the child is gone (its import failed, say): drawn in this process
            self.close()

    def result(self):
        """The submitted call's value; its exception raised here as its own. A child that ended
        without an answer (killed, say) leaves the call to this process."""
        function, args, kwargs = self._call
        if self._pid is None:
            return function(*args, **kwargs)
        pid, self._pid = self._pid, None
        try:
            with os.fdopen(self._results, "rb") as results:
                answer = results.read()
        finally:
            os.waitpid(pid, 0)
        if not answer:
            return function(*args, **kwargs)
        ok, value = pickle.loads(answer)
        if not ok:
            raise value
        return value

    def close(self) -> None:
        """End the child without waiting for an answer (the command stopped before its figure)."""
        if self._pid is not None:
            pid, self._pid = self._pid, None
            if self._jobs is not None:
                os.close(self._jobs)
            else:  # a call was sent: the figure is not wanted any more
                os.kill(pid, signal.SIGTERM)
            os.close(self._results)
            os.waitpid(pid, 0)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def _child(jobs: int, results: int) -> None:
    """Import matplotlib, run the one call read from ``jobs``, write (ok, value) to ``results``,
    and leave without the parent's exit handlers."""
    status = 1
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C stops the parent; the pipe's end stops this
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        from slosh_bif.report.plotting import pyplot

        pyplot()
        with os.fdopen(jobs, "rb") as stream:
            data = stream.read()
        if data:  # empty: the parent ended the child without a call
            function, args, kwargs = pickle.loads(data)
            try:
                answer = (True, function(*args, **kwargs))
            except Exception as err:  # the parent raises it as the call's own
                answer = (False, err)
            with os.fdopen(results, "wb") as stream:
                try:
                    pickle.dump(answer, stream)
                except Exception as err:  # an answer that does not pickle
                    pickle.dump((False, RuntimeError(f"the plot's answer could not be sent: {err}")), stream)
        status = 0
    finally:
        os._exit(status)
