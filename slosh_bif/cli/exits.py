"""How a command ends, in bounded time: SIGTERM and Ctrl-C raised in the main thread (so that one
path stops the workers, keeps what is done and exits 143 or 130), and a watch that ends the
process if, once stopped or once its work is done, it is still held by a thread or a child
process :data:`EXIT_WAIT` seconds later.

Why the watch: a stopped family scan once hung with its workers gone, the main process waiting
on a lock (not reproduced since). A process pool's manager thread that waits forever on the queue
of a killed worker (a class of deadlocks CPython's ProcessPoolExecutor had, python/cpython#125451)
would hold a process that way, in the pool's shutdown or in the interpreter's exit, which joins
that thread.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading

from slosh_bif.cli.common import Terminated

__all__ = ["EXIT_WAIT", "leave_within", "stop_signals"]

EXIT_WAIT = 30.0
"""Seconds a stopped command, or an ordinary exit, may wait for the threads and child processes
still alive (a pool's manager thread, a cluster's client) before the process leaves without them."""


def leave_within(seconds: float, status: int, after: str) -> None:
    """Start the watch: if the process has not ended ``seconds`` from now, say so (``after``: what
    it was waiting after, "the stop" or "the exit") and leave with ``status``."""

    def leave():
        print(
            f"slosh-bif: {after} waited {seconds:g} s for a thread or child process; leaving without it",
            file=sys.stderr,
            flush=True,
        )
        os._exit(status)

    watch = threading.Timer(seconds, leave)
    watch.daemon = True
    watch.start()


@contextlib.contextmanager
def stop_signals(wait: float | None = None):
    """SIGTERM raises :class:`~slosh_bif.cli.common.Terminated` and Ctrl-C KeyboardInterrupt in the
    main thread, each starting the watch (``wait`` seconds, :data:`EXIT_WAIT` by default); Ctrl-C
    is left alone where it was ignored when the command started (a job started in the background
    keeps ignoring it). Outside the main thread, signals stay as they are."""
    wait = EXIT_WAIT if wait is None else wait

    def on_sigterm(_signum, _frame):
        leave_within(wait, 143, "the stop")
        raise Terminated("stopped")

    def on_sigint(_signum, _frame):
        leave_within(wait, 130, "the stop")
        raise KeyboardInterrupt

    try:
        previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, on_sigterm)}
    except ValueError:  # not the main thread
        yield
        return
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        previous[signal.SIGINT] = signal.signal(signal.SIGINT, on_sigint)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
