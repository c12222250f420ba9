"""A scan for every family of 2pi-orbits of (9) run side by side on a pool (local processes or a
dask cluster), with the sequential scan's result (:func:`~slosh_bif.orbits.scan.scan_families`).

The starts (simulations of (9) and Newton, :func:`~slosh_bif.orbits.scan_starts.start_jobs`) are
independent: they run as tasks and are read in their order. The families are not: the sequential
scan traces a start's family beside the branches the starts before it traced (a switched branch
already known is not traced again, names stay unique), and a start on a known branch traces
nothing. So the starts are dealt with in order here too, and the families of the next starts
that lie on no branch known so far are traced ahead, beside the branches known when they are
sent. When a start's turn comes, the questions its trace put to those branches
(:func:`~slosh_bif.orbits.known.on_known`) are answered again among the branches known by then:
if every answer holds, the traced family is the sequential one but for its branches' names,
which are given as the sequential run gives them; if one does not, the family is traced again.
A family traced ahead for a start that turns out to lie on a known branch is dropped.
"""

from __future__ import annotations

import contextlib
import dataclasses
import time
from concurrent.futures import FIRST_COMPLETED, wait

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.orbits.families import trace_new_family
from slosh_bif.orbits.known import answers_hold
from slosh_bif.orbits.orbit_branch import OrbitFamily, images, renamed, unique_name
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.switch_ahead import switch_threads, threads
from slosh_bif.report.tasks import Task, timed

__all__ = ["starts_side_by_side", "families_side_by_side", "family_task", "named_as_sequential", "HEARTBEAT"]

HEARTBEAT = 15.0  # seconds between the lines saying that the family awaited is still being traced


def starts_side_by_side(jobs, executor, say, tasks: list | None = None) -> list:
    """The converged starts of ``jobs`` (``(function, arguments, label)`` from
    :func:`~slosh_bif.orbits.scan_starts.start_jobs`), run on ``executor`` and read in order;
    ``tasks`` gets a :class:`~slosh_bif.report.tasks.Task` for each."""
    futures = [executor.submit(timed, function, *arguments) for function, arguments, _ in jobs]
    converged = []
    for future, (_, _, label) in zip(futures, jobs):
        (found, messages), seconds = future.result()
        if tasks is not None:
            tasks.append(Task(len(tasks), "start", label, seconds, len(found)))
        for message in messages:
            say(message)
        converged += found
    return converged


def family_task(start, known, tracing: dict, share: int | None = None):
    """(family or None, why not, progress messages, questions asked of ``known``, seconds) of one
    start, traced beside the branches ``known`` (in a worker); the seconds are reported only.
    ``share``: threads its switches may use (:func:`~slosh_bif.orbits.switch_ahead.switch_threads`;
    the worker's default where None)."""
    traced, seconds = timed(_family, start, known, tracing, share)
    return (*traced, seconds)


def _family(start, known, tracing: dict, share):
    messages, asked = [], []
    try:
        with switch_threads(share) if share else contextlib.nullcontext():
            family = trace_new_family(
                start.params,
                start.y0,
                known,
                found_from=start.found_from,
                progress=messages.append,
                asked=asked,
                **tracing,
            )
    except ConvergenceError as error:
        return None, str(error), messages, asked
    return family, None, messages, asked


def named_as_sequential(family: OrbitFamily, known) -> OrbitFamily:
    """``family``'s branches named as a trace beside ``known`` names them (each kind, kind-2, ...
    unique among ``known`` and the family's branches before it), origins rewritten to match."""
    names, taken = {}, list(known)
    for ob in family.branches:
        names[ob.name] = unique_name(ob.kind, taken)
        taken.append(dataclasses.replace(ob, name=names[ob.name]))
    return OrbitFamily(family.params, family.param, renamed(family.branches, names))


def _same_orbit(a, b, segments: int) -> bool:
    """Whether two starts are one orbit (or mirror images) at one parameter set."""
    if a.params != b.params:
        return False
    problem = ShootingProblem(a.params, segments=segments)
    x = problem.initial_states(b.y0)
    return any(
        np.linalg.norm(y - x) <= 1e-6 * (1 + np.linalg.norm(x))
        for y in images(problem, problem.initial_states(a.y0))
    )


def families_side_by_side(starts: list, branches: list, *, executor, first: int, tracing: dict, take: dict):
    """Deal with ``starts[first:]`` in order, as the sequential scan does, their families traced
    on ``executor`` (``executor.threads`` at once), ahead of their turn where they may be new.

    ``take``: the scan's steps, run here in order: ``is_known(start)`` (says why, if so),
    ``lies_on(start)`` (the same question, silent), ``add(family)`` (into ``branches``),
    ``keep(k, branches)`` (or None) after the k-th start, ``say``, and ``record(k, family,
    seconds)`` for each family traced (its result read: a family traced again is recorded
    twice). While the family whose turn it is runs on a worker, a line every :data:`HEARTBEAT`
    seconds says so (its own progress lines come when it is done, in the sequential order).
    """
    say, keep = take["say"], take["keep"]
    slots = max(1, int(getattr(executor, "threads", 1)))
    # Local processes share this machine's cores: a family's switches get its share of them.
    share = max(1, threads() // slots) if getattr(executor, "place", "") == "local processes" else None
    segments = tracing["shooting"].segments
    ahead, dropped, considered = {}, [], first  # start index -> future; futures no longer wanted
    current = first

    def send(j):
        ahead[j] = executor.submit(family_task, starts[j], list(branches), tracing, share)

    def top_up():
        nonlocal considered
        dropped[:] = [f for f in dropped if not f.done()]
        while considered < len(starts) and len(ahead) + len(dropped) < slots:
            j, considered = considered, considered + 1
            if not take["lies_on"](starts[j]) and not any(
                _same_orbit(starts[i], starts[j], segments) for i in [current, *ahead]
            ):
                send(j)

    for k in range(first, len(starts)):
        current, considered = k, max(considered, k + 1)
        future = ahead.pop(k, None)
        if take["is_known"](starts[k]):
            if future is not None and not future.cancel():
                dropped.append(future)
        else:
            say(f"scan: a new family from {starts[k].found_from}")
            for attempt in range(2):
                if future is None:
                    send(k)
                    future = ahead.pop(k)
                began = said = time.monotonic()
                while not future.done():
                    top_up()
                    wait([future, *ahead.values(), *dropped], timeout=HEARTBEAT, return_when=FIRST_COMPLETED)
                    if not future.done() and time.monotonic() - said >= HEARTBEAT:
                        said = time.monotonic()
                        say(
                            f"scan: the family from {starts[k].found_from} is being traced on a worker "
                            f"({said - began:.0f} s; {len(ahead)} more traced ahead)"
                        )
                family, err, messages, asked, seconds = future.result()
                take["record"](k, family, seconds)
                if answers_hold(asked, branches):
                    break
                say(f"scan: the family from {starts[k].found_from} met branches traced since: traced again")
                future = None
            for message in messages:
                say(message)
            if family is None:
                say(f"scan: no family traced from {starts[k].found_from}: {err}")
            else:
                take["add"](named_as_sequential(family, branches))
        if keep is not None:
            keep(k + 1, branches)
        top_up()
    for future in dropped:
        future.cancel()
