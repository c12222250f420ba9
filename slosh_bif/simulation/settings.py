"""How a time response is computed, as objects passed whole (the model, its integrator and
sampling; the random forcing of eq. (47)), and where the cells of a sweep run.

* :class:`SimulationSettings`: the model, (8) or (9), the sample step and the integrator's
  tolerances and backend (:func:`~slosh_bif.simulation.direct.simulate`, the regime classifier);
* :class:`Noise`: the band-limited noise of (47), with the seed that makes a run reproducible;
* :class:`Workers`: the executor of a sweep's cells (a Dask cluster's, or local processes).
"""

from __future__ import annotations

import dataclasses

__all__ = ["SimulationSettings", "SIMULATION", "Noise", "Workers", "LOCAL"]


@dataclasses.dataclass(frozen=True)
class SimulationSettings:
    """``model``: "smooth" (9) or "impact" (8); ``sample_step``: the spacing of the stored samples
    (at most 0.05 for (8)); ``rtol``, ``atol``: the integrator's tolerances on (9); ``backend``:
    "auto", "numba" or "scipy" (:func:`~slosh_bif.flows.smooth.integrator.resolve_backend`)."""

    model: str = "smooth"
    sample_step: float = 0.02
    rtol: float = 1e-9
    atol: float = 1e-11
    backend: str = "auto"

    def replace(self, **changes) -> SimulationSettings:
        return dataclasses.replace(self, **changes)


SIMULATION = SimulationSettings()


@dataclasses.dataclass(frozen=True)
class Noise:
    """The random forcing of (47): standard deviation ``std`` (sigma_bar), band-limited below
    ``cutoff`` (in units of the forcing frequency), drawn from ``seed``."""

    std: float
    seed: int | None = None
    cutoff: float = 10.0


@dataclasses.dataclass(frozen=True)
class Workers:
    """Where the cells of a sweep run: ``executor`` (any ``concurrent.futures.Executor``, e.g. a
    Dask cluster's, :class:`~slosh_bif.simulation.sweep.ClusterExecutor` ``(client)``, whose tasks
    hold their workers' BLAS to one thread), or by default ``max_workers`` local processes (one
    per core when None)."""

    executor: object = None
    max_workers: int | None = None


LOCAL = Workers()
