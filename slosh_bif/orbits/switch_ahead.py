"""The switches of a family of orbits of (9) traced ahead of their turn, side by side in threads.

A family works through its queue of switch points in order (:func:`~slosh_bif.orbits.families.
trace_new_family`), and what one switch gives, the branch traced from the parent's point and its
orbits' measures, depends on the parent and the point alone. So the switches next in the queue
can be traced while the one whose turn it is runs, and the family assembled from them in the
queue's order is the one traced one switch at a time. The arcs' integrations, most of a trace,
run compiled and release the GIL, so threads share the cores; a trace ahead runs on problems of
its own (the shooting problem keeps per-object caches), keeps its progress lines until its turn,
and is abandoned at its next point once the family no longer needs it (the point left the queue,
or the family has its branches).

How many traces run at once is an execution setting, not part of a result:
:func:`switch_threads` sets it for a block (the usable cores by default; a scan's local worker
processes take their share of the cores).
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import threading
from concurrent.futures import ThreadPoolExecutor

__all__ = ["switch_threads", "threads", "Abandoned", "SwitchesAhead"]

_THREADS: contextvars.ContextVar[int | None] = contextvars.ContextVar("switch_threads", default=None)


@contextlib.contextmanager
def switch_threads(count: int):
    """Trace at most ``count`` switches of a family at once inside the block (1: one at a time)."""
    if not (isinstance(count, int) and count >= 1):
        raise ValueError(f"switch threads must be an integer >= 1; got {count!r}")
    token = _THREADS.set(count)
    try:
        yield
    finally:
        _THREADS.reset(token)


def threads() -> int:
    """Threads a family's work takes here (its switches traced at once, its special points judged
    at once: :func:`~slosh_bif.orbits.criticality.family_criticality`): as :func:`switch_threads`
    set, else one per usable core."""
    count = _THREADS.get()
    if count is not None:
        return count
    usable = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else range(os.cpu_count() or 1)
    return max(1, len(usable))


class Abandoned(Exception):
    """Raised inside a trace ahead that the family no longer needs (at its next point)."""


class _Trace:
    """One switch traced ahead: its future, the progress lines it has said so far, and whether
    they go straight through (its turn came) or are kept."""

    def __init__(self):
        self.future = None
        self.kept: list = []
        self.live = None
        self.lock = threading.Lock()
        self.abandoned = threading.Event()

    def check(self) -> None:
        """Raise :class:`Abandoned` if the family no longer needs this trace."""
        if self.abandoned.is_set():
            raise Abandoned

    def say(self, message: str) -> None:
        self.check()
        with self.lock:
            if self.live is None:
                self.kept.append(message)
            else:
                self.live(message)

    def go_live(self, say) -> None:
        with self.lock:
            for message in self.kept:
                say(message)
            self.kept, self.live = [], say


class SwitchesAhead:
    """The switches of one family, each run once: :meth:`take` returns a switch's result in turn.

    ``count`` traces at once (1: each in this thread when its turn comes, nothing ahead); ``say``
    gets every progress line in the queue's order. A trace ahead that ends frees its thread for the
    next switch of the queue at once, not at the next turn. Use as a context manager: leaving the
    block abandons the traces not taken."""

    def __init__(self, count: int, say):
        self.count, self.say = count, say
        self.ahead: dict = {}  # key -> _Trace
        self.upcoming: list = []  # (key, run) of the switches after the one whose turn it is
        self.started = self.unused = 0  # traces started ahead; of them abandoned
        self.lock = threading.RLock()  # self.ahead changes here and when a trace ahead ends
        self.closed = False
        self.pool = ThreadPoolExecutor(max_workers=count, thread_name_prefix="switch") if count > 1 else None

    def __enter__(self):
        return self

    def __exit__(self, kind, error, trace):
        with self.lock:
            self.closed = True
            for key in list(self.ahead):
                self._abandon(key)
        if self.pool is not None:
            self.pool.shutdown(wait=kind is None, cancel_futures=True)
        if kind is None and self.started:
            self.say(f"switches traced ahead in threads: {self.started}, {self.unused} of them not needed")
        return False

    def _abandon(self, key) -> None:
        self.ahead.pop(key).abandoned.set()
        self.unused += 1

    def take(self, key, run, upcoming=()):
        """The result of ``run(say, trace)`` for the switch ``key``, whose turn it is (its
        progress lines said in order; its exception raised here). ``upcoming``: ``(key, run)`` of
        the switches that may come next, in the queue's order; the first of them are traced in
        the idle threads, and traces ahead that are no longer among them are abandoned. ``run``
        gets ``trace`` None when it runs here in its turn, else the trace ahead it runs for (its
        ``check()`` raises :class:`Abandoned` once it is not needed)."""
        with self.lock:
            wanted = {k for k, _ in upcoming}
            for k in [k for k in self.ahead if k not in wanted and k != key]:
                self._abandon(k)
            traced = self.ahead.pop(key, None)
            self.upcoming = [(k, r) for k, r in upcoming if k != key]
            self._fill()
        if traced is None:
            return run(self.say, None)
        traced.go_live(self.say)
        return traced.future.result()

    def _fill(self) -> None:
        """Start the first upcoming switches not started while fewer than ``count - 1`` traces
        ahead run (the switch whose turn it is takes the last thread)."""
        for k, r in self.upcoming:
            if self.pool is None or self.closed:
                return
            if sum(not traced.future.done() for traced in self.ahead.values()) >= self.count - 1:
                return
            if k not in self.ahead:
                self._start(k, r)

    def _refill(self, _future) -> None:
        with self.lock:
            self._fill()

    def _start(self, key, run) -> None:
        self.started += 1
        traced = self.ahead[key] = _Trace()
        traced.future = self.pool.submit(run, traced.say, traced)
        traced.future.add_done_callback(self._refill)  # at once if it is done already
