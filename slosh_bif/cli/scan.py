"""``slosh-bif shoot --start scan``: every family of periodic orbits of (9) over a range
(:func:`~slosh_bif.orbits.scan.scan_families`), sequentially, on local worker processes or on a
dask cluster (``--scheduler``), resumable; the branches are the same in each case."""

from __future__ import annotations

import contextlib
import dataclasses

from slosh_bif.cli.common import check_workers, progress, state0_of, sweep_executor, throttled

__all__ = ["scan_from_args"]


def scan_from_args(args, params, interval, rtol: float, tracing: dict):
    """The scan's OrbitFamily for ``shoot``'s (or ``compare``'s) arguments over ``interval``;
    ``tracing``: the shooting, branching and continuation settings."""
    from slosh_bif.orbits.scan import scan_families
    from slosh_bif.orbits.settings import StartSettings
    from slosh_bif.report.files import Resume, pickle_store

    if getattr(args, "workers", None) is not None:
        check_workers(args)
    settings = dict(
        params=params.as_dict(),
        param=interval.name,
        range=[interval.lo, interval.hi],
        points=args.scan_points,
        random=args.scan_random,
        seed=args.seed,
        settle=args.settle,
        segments=args.segments,
        switch=not args.no_switch,
        max_branches=args.max_branches,
        rtol=rtol,
        backend=args.backend,
        options=dataclasses.asdict(tracing["options"]),
    )
    done, keep = pickle_store(args.out / "scan.pickle", settings, resume=getattr(args, "resume", False))
    if done is not None:
        progress(
            f"resuming: {done[0]} converged starts already dealt with, {len(done[1])} "
            f"branch(es) traced, in {args.out / 'scan.pickle'}"
        )
    starts = StartSettings(
        points=args.scan_points, settle=args.settle, random_starts=args.scan_random, seed=args.seed
    )
    with _pool(args) as executor:
        return scan_families(
            params,
            state0_of(args, params),
            starts=starts,
            progress=throttled(progress),
            resume=Resume(done, keep),
            interval=interval,
            executor=executor,
            **tracing,
        )


@contextlib.contextmanager
def _pool(args):
    """The cluster's executor (``--scheduler``), local worker processes (``--workers`` above 1),
    or None (this process)."""
    with sweep_executor(args) as cluster:
        if cluster is not None:
            if getattr(args, "workers", None) is not None:
                cluster.threads = args.workers
            yield cluster
            return
        from slosh_bif.simulation.sweep import local_pool

        with local_pool(getattr(args, "workers", None) or 1) as pool:
            yield pool
