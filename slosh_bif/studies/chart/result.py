"""What a chart is and how it is made, for the charts of both full models: the result
(:class:`Chart`: the curves of orbit bifurcations in (sigma, second parameter), the slow flow's
critical forcing of (46) beside them, what stopped early), its settings, and the checks of a
box and of the worker count that run before any work."""

from __future__ import annotations

import dataclasses
import os

from slosh_bif.model.params import Params
from slosh_bif.orbits.shooting import PARAMETERS

__all__ = ["Chart", "ChartSettings", "check_box", "chart_workers", "where"]


@dataclasses.dataclass(frozen=True)
class Chart:
    """The chart's pieces: the orbit family it started from, the curves, the slow flow's critical
    curve (None where (46) has none in the range), whether every start was tried (``status``) and
    the starts that gave no curve (``failures``, each with its reason)."""

    params: Params
    sigma_range: tuple
    abar_range: tuple  # the range of ``second``
    family: object
    curves: list
    slow_flow_critical: object
    seconds: float
    status: str = "complete"  # or why the curves stopped early ("interrupted (SIGINT) after ...")
    second: str = "Abar"  # the chart's second parameter
    failures: tuple = ()  # CurveFailure of each start that gave no curve
    # the model whose orbits the curves are of: the smooth model (9) or the impact model (8)
    orbits: str = "(9)"
    tasks: tuple = ()  # a Task per curve traced (start, seconds, points), in the order they finished
    # (sigma, family in the second parameter) of each seed (an OrbitFamily of (9), an ImpactFamily of
    # (8)): an answer at that sigma apart from the curves (reading.seed_disagreements)
    seeds: tuple = ()
    # (sigma, good) of each branch in sigma along the box's lowest Abar, traced from a seed whose
    # stable orbits with wall contact reach it: good where Abar_c lies below the box
    # (bottom.below_bottom)
    bottom: tuple = ()

    @property
    def reads_critical(self) -> bool:
        """Whether the critical forcing Abar_c is read off this chart: Abar is its second
        parameter and every curve was traced (off part of the curves the lowest boundary may be a
        higher curve's, and the stable orbits below it would be followed down at every sigma)."""
        return self.second == "Abar" and self.status == "complete"

    @property
    def incomplete(self) -> list:
        """Why the chart is not the whole answer, one line each: curves cut short, starts that gave no
        curve."""
        cut = [
            f"curve {k} ({c.kind} from {c.origin}): {c.status}"
            for k, c in enumerate(self.curves)
            if c.status != "ok"
        ]
        return cut + [f"no {f.kind} curve from {f.origin}: {f.reason}" for f in self.failures]


@dataclasses.dataclass(frozen=True)
class ChartSettings:
    """How a chart finds its curves' starts and shares the work.

    Attributes
    ----------
    settle : int
        Forcing periods of the simulation from the initial state that finds the start orbit.
    seeds : int
        Orbits of the primary branch, at evenly spread values of sigma, each continued in the
        second parameter (their folds and period doublings start curves too).
    workers : int or None
        Processes tracing curves side by side (None: every core, or with ``executor`` the
        cluster's threads); the result does not depend on it.
    model : str
        The slow flow whose least forcing of the upper branch is drawn beside the curves.
    """

    settle: int = 150
    seeds: int = 7
    workers: int | None = None
    model: str = "slowflow"
    #: a cluster's ``concurrent.futures`` executor (:class:`~slosh_bif.simulation.sweep.ClusterExecutor`,
    #: dask's): the curves are its tasks, ``workers`` of them at once; None: local processes
    executor: object = None

    @property
    def slots(self) -> int:
        """How many curves are traced at once."""
        if self.workers is None and self.executor is not None:
            return max(1, int(getattr(self.executor, "threads", 1)))
        return chart_workers(self.workers)

    def __post_init__(self):
        for name, low in (("settle", 1), ("seeds", 0)):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= low):
                raise ValueError(f"ChartSettings.{name} must be an integer >= {low}; got {value!r}")
        chart_workers(self.workers)


def check_box(params: Params, sigma_range, second_range, second: str = "Abar"):
    """One line before any work unless ``second`` is a real field other than sigma, the box is
    not empty, both ends of the second range are admissible values (Abar >= 0, eps > 0, a real
    restitution coefficient, ...), the parameter set lies inside the box and its vessel has a
    positive stiffness (the charts start from a simulation there)."""
    if second == "sigma" or second not in PARAMETERS:
        raise ValueError(
            "the chart's second parameter must be one of "
            f"{', '.join(p for p in PARAMETERS if p != 'sigma')} (sigma is the first); got "
            f"{second!r}"
        )
    (s0, s1), (a0, a1) = sigma_range, second_range
    if not (s0 < s1 and a0 < a1):
        raise ValueError(
            f"empty box: sigma in [{s0}, {s1}], {second} in [{a0}, {a1}] (need sigma_min < "
            f"sigma_max and {second}_min < {second}_max)"
        )
    for end in (a0, a1):
        try:
            params.replace(**{second: end})
        except ValueError as err:
            raise ValueError(
                f"the box's {second} range [{a0:g}, {a1:g}] leaves the parameter's range: {err}"
            ) from None
    if not (s0 <= params.sigma <= s1 and a0 <= getattr(params, second) <= a1):
        raise ValueError(
            f"the start (sigma = {params.sigma:g}, {second} = {getattr(params, second):g}) lies "
            f"outside the box sigma in [{s0:g}, {s1:g}], {second} in [{a0:g}, {a1:g}]: the chart's "
            f"family starts at the set's own values; move them inside with --set sigma=... --set "
            f"{second}=..."
        )
    params.require_positive_stiffness()


def chart_workers(workers) -> int:
    """The number of processes tracing curves: ``workers``, or every core for None."""
    if workers is None:
        return os.cpu_count() or 1
    if not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers must be an integer >= 1; got {workers!r}")
    return workers


def where(settings: ChartSettings) -> str:
    """Where the curves are traced, for the progress line."""
    if settings.executor is not None:
        return f"{settings.slots} at a time on {getattr(settings.executor, 'place', 'the cluster')}"
    return f"on {settings.slots} process(es)"
