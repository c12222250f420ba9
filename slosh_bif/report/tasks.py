"""A distributed run's tasks (a chart's curves, a family scan's starts and families): how long each
took where it ran, written as ``tasks.csv``, and what that says of more workers. The projection
schedules the recorded durations as the run does (in start order, each task to the first free
worker; the work the calling process does alone, such as a chart's family and seeds, left out):
its time on P workers is at least the longest task and at least the total over P, so beyond total
/ longest workers only splitting the longest tasks would help. The durations are wall-clock
times, reported and never used for a result."""

from __future__ import annotations

import dataclasses
import heapq
import time

from slosh_bif.report.tables import write_rows

__all__ = ["Task", "TASK_COLUMNS", "timed", "write_tasks_csv", "projected_seconds", "scaling_line"]

TASK_COLUMNS = ("start", "kind", "origin", "seconds", "points")
PROJECTED = (1, 2, 8, 32, 128)  # worker counts of the projection


@dataclasses.dataclass(frozen=True)
class Task:
    """One task: its start (index, kind, origin), its duration in seconds (in the process that ran
    it) and its points (a curve's or a family's; a scan's start: the orbits it converged to; 0:
    none)."""

    start: int
    kind: str
    origin: str
    seconds: float
    points: int


def timed(function, *arguments):
    """(``function(*arguments)``, the seconds it took): a task's result with its duration (run
    where the task runs, a worker say, so that the seconds are its own)."""
    began = time.perf_counter()
    return function(*arguments), time.perf_counter() - began


def write_tasks_csv(tasks, path):
    """One row per task, in start order."""
    rows = (
        dataclasses.asdict(t) | {"seconds": f"{t.seconds:.3f}"} for t in sorted(tasks, key=lambda t: t.start)
    )
    return write_rows(rows, TASK_COLUMNS, path)


def projected_seconds(tasks, workers: int) -> float:
    """The tasks' time on ``workers`` workers: the recorded durations in start order, each to
    the worker that is free first."""
    if workers < 1:
        raise ValueError(f"workers must be >= 1; got {workers!r}")
    free = [0.0] * min(workers, max(len(tasks), 1))
    for task in sorted(tasks, key=lambda t: t.start):
        heapq.heapreplace(free, free[0] + task.seconds)
    return max(free)


def scaling_line(tasks, what: str = "curve") -> str:
    """One line: the work, the longest task and the projected times on :data:`PROJECTED` workers
    (``what``: the tasks' name, "curve" for a chart's)."""
    if not tasks:
        return f"no {what} task was run"
    total = sum(t.seconds for t in tasks)
    longest = max(tasks, key=lambda t: t.seconds)
    projected = ", ".join(f"{projected_seconds(tasks, p):.1f}" for p in PROJECTED)
    return (
        f"{len(tasks)} {what} tasks, {total:.1f} s of work; the longest, {longest.seconds:.1f} s "
        f"({longest.kind} from {longest.origin}), bounds any number of workers; projected on "
        f"{', '.join(map(str, PROJECTED))} workers: {projected} s"
    )
