"""Response regimes of the forced system (section 4.2, Figs. 10-13) and maps of them.

A simulated response (:func:`slosh_bif.simulation.direct.simulate`) is judged after its transient from
three measurements:

* the impact sequence: impacts per forcing period, and wall-to-wall crossings per period (side
  changes between consecutive impacts). 1:1 resonance means two crossings a period; the number
  of impacts can be larger, because the particle often strikes the same wall twice;
* the envelope of X: its peak |X| in each forcing period (the amplitude A of eq. 22), its 10th and
  90th percentiles and how often it collapses and recovers;
* the projection on the slow invariant manifold (36): (A, alpha) per period, alpha the peak of
  |w - X|, against the stable branch alpha_S+(A) and its end A_min.

Rules, in order (``THRESHOLDS`` holds the numbers):

``non-resonant``
    fewer than 0.1 impacts a period (or the impact model's particle sticks to a wall): the
    vessel moves as a linear oscillator and the particle is not engaged (Fig. 11).
``periodic-resonant``
    about two crossings a period, an envelope varying by less than 30 %, above A_min, and
    within 15 % of the stable branch S+ in the manifold's plane (Figs. 10, 13).
``strongly-modulated``
    an envelope varying by 30 % or more that collapses to within twice A_min at least twice
    (intermittent capture and escape, Fig. 12).
``other``
    anything else (e.g. a period-2 or quasi-periodic response, or noise-driven modulation far
    above A_min).
``diverged``
    the run left every bounded response (:func:`~slosh_bif.simulation.direct.diverged_beyond`)
    and was stopped there.

:func:`regime_map` classifies a (sigma, Abar) grid through any ``concurrent.futures`` executor.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.model.manifold import project_on_manifold
from slosh_bif.model.params import Params
from slosh_bif.model.presets import CLASSIFY_TMAX
from slosh_bif.model.restitution.on_manifold import ManifoldLaw
from slosh_bif.report.files import Resume
from slosh_bif.simulation.direct import MAX_SAMPLES, simulate
from slosh_bif.simulation.settings import LOCAL, SIMULATION, SimulationSettings, Workers
from slosh_bif.simulation.sweep import submit_cells

__all__ = [
    "REGIMES",
    "THRESHOLDS",
    "RegimeSummary",
    "classify",
    "RegimeMap",
    "regime_map",
    "submit_regime_map",
    "PendingRegimeMap",
    "check_run_length",
]

REGIMES = (
    "periodic-resonant",
    "non-resonant",
    "strongly-modulated",
    "free-decay",
    "other",
    "diverged",
    "failed",
)

THRESHOLDS = {
    "impacts_for_engagement": 0.1,  # impacts per period below this: the particle is not engaged
    "crossings_for_resonance": (1.5, 2.5),  # wall-to-wall crossings per period in 1:1 resonance
    "steady_modulation": 0.3,  # (A90 - A10) / A90 below this: constant envelope
    "manifold_distance": 0.15,  # median relative distance of alpha from alpha_S+(A)
    "collapse_factor": 2.0,  # a collapse reaches below this many A_min
    "collapses": 2,  # repeated: at least this many collapses
}


@dataclasses.dataclass(frozen=True)
class RegimeSummary:
    """What :func:`classify` measured and concluded (all after the transient).

    The fields are the keys of ``summary.json``; ``reason`` says which rule decided.
    """

    regime: str
    reason: str
    impacts_per_period: float
    crossings_per_period: float
    envelope_min: float
    envelope_max: float
    envelope_p10: float
    envelope_p90: float
    modulation: float
    collapses: int
    A_min: float
    manifold_distance: float
    transient: float
    periods: float

    @classmethod
    def failed(cls, reason: str, transient: float) -> "RegimeSummary":
        """The record of a run that failed (regime ``"failed"``, the reason kept, every measurement NaN)."""
        nan = math.nan
        return cls("failed", reason, nan, nan, nan, nan, nan, nan, nan, 0, nan, nan, transient, nan)

    @classmethod
    def not_computed(cls, reason: str, transient: float) -> "RegimeSummary":
        """The record of a grid point a stopped run did not reach (regime ``"not computed"``)."""
        return dataclasses.replace(cls.failed(reason, transient), regime="not computed")

    def as_dict(self) -> dict:
        return {
            k: (v if not isinstance(v, float) or math.isfinite(v) else None)
            for k, v in dataclasses.asdict(self).items()
        }

    @classmethod
    def from_dict(cls, record: dict) -> "RegimeSummary":
        """The inverse of :meth:`as_dict` (None back to NaN): a stored cell, bit for bit."""
        return cls(
            **{
                k: (math.nan if record[k] is None else record[k])
                for k in (f.name for f in dataclasses.fields(cls))
            }
        )


def _collapses(A, low, high):
    """Number of times the envelope falls below ``low`` after having been above ``high``."""
    count, armed = 0, False
    for a in A:
        if a >= high:
            armed = True
        elif a <= low and armed:
            count += 1
            armed = False
    return count


def classify(simulation, *, transient: float | None = None) -> RegimeSummary:
    """Classify a :class:`~slosh_bif.simulation.direct.Simulation` after ``transient`` (default: its first
    half)."""
    sim = simulation
    t0, t1 = float(sim.t[0]), float(sim.t[-1])
    if sim.status == "diverged":
        return dataclasses.replace(
            RegimeSummary.failed(sim.message, math.nan if transient is None else transient), regime="diverged"
        )
    if transient is None:
        transient = t0 + 0.5 * (t1 - t0)
    if sim.status == "sticking" and np.isfinite(transient) and t1 - 4 * np.pi <= transient:
        # (8) without a sticking phase ends where the particle sticks: nothing after it to measure
        reason = f"the particle sticks to a wall before the judged window ({sim.message})"
        return dataclasses.replace(RegimeSummary.failed(reason, transient), regime="non-resonant")
    if not (np.isfinite(transient) and t0 <= transient < t1 - 4 * np.pi):
        raise ValueError(
            f"transient must leave at least two forcing periods of the run [{t0:g}, {t1:g}]; got "
            f"{transient!r}"
        )
    params: Params = sim.params
    keep = sim.t >= transient
    periods = (t1 - transient) / (2 * np.pi)
    late = sim.impact_t >= transient
    impacts = float(np.sum(late)) / periods
    sides = sim.impact_side[late]
    crossings = float(np.sum(sides[1:] != sides[:-1])) / periods
    proj = project_on_manifold(sim.t[keep], sim.y[:, keep])
    A = proj.A
    law = ManifoldLaw(params)
    A_min = law.A_min
    p10, p90 = (float(v) for v in np.percentile(A, [10, 90]))
    modulation = (p90 - p10) / p90 if p90 > 0 else 0.0
    on = (A >= A_min) & (A <= law.A_max)  # S+ ends at A_max where (39) folds (pbar != 0)
    if np.any(on):
        target = law.alpha(A[on])
        distance = float(np.median(np.abs(proj.alpha[on] - target) / target))
    else:
        distance = math.inf
    T = THRESHOLDS
    collapses = _collapses(A, T["collapse_factor"] * A_min, 0.5 * (p10 + p90))
    lo, hi = T["crossings_for_resonance"]
    if params.Abar == 0 and sim.noise is None:
        # Without forcing every response decays: its envelope's collapses are the decay, not modulation.
        regime, reason = (
            "free-decay",
            f"no forcing (Abar = 0): the envelope decays from {float(A.max()):.3g} to "
            f"{float(A[-1]) if A.size else float('nan'):.3g}",
        )
    elif sim.status == "sticking":
        regime, reason = "non-resonant", f"the particle sticks to a wall ({sim.message})"
    elif impacts < T["impacts_for_engagement"]:
        regime, reason = "non-resonant", f"{impacts:.3g} impacts per period after the transient"
    elif (
        lo <= crossings <= hi
        and modulation < T["steady_modulation"]
        and p10 >= A_min
        and distance < T["manifold_distance"]
    ):
        regime, reason = (
            "periodic-resonant",
            (
                f"{crossings:.3g} wall-to-wall crossings per period, envelope varies "
                f"{100 * modulation:.1f} %, "
                f"{100 * distance:.1f} % from the stable manifold branch"
            ),
        )
    elif modulation >= T["steady_modulation"] and collapses >= T["collapses"]:
        regime, reason = (
            "strongly-modulated",
            (
                f"envelope varies {100 * modulation:.0f} % and collapses {collapses} times below "
                f"{T['collapse_factor']:g} A_min = {T['collapse_factor'] * A_min:.3g}"
            ),
        )
    else:
        where = (
            f"{100 * distance:.1f} % from the stable manifold branch"
            if np.isfinite(distance)
            else f"the envelope beyond S+, which ends at A = {law.A_max:.4g}"
            if np.any(A > law.A_max)
            else "the envelope below S+"
        )
        regime, reason = (
            "other",
            f"{crossings:.3g} crossings per period, envelope varies {100 * modulation:.1f} %, "
            f"{collapses} collapses, {where}",
        )
    return RegimeSummary(
        regime,
        reason,
        impacts,
        crossings,
        float(A.min()),
        float(A.max()),
        p10,
        p90,
        modulation,
        collapses,
        float(A_min),
        distance,
        float(transient),
        periods,
    )


# --- regime maps ------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class RegimeMap:
    """Regimes on a grid: ``regime[i, j]`` at ``sigma[j]``, ``Abar[i]``; ``summaries`` likewise."""

    params: Params
    sigma: np.ndarray
    Abar: np.ndarray
    regime: np.ndarray
    summaries: list
    tmax: float
    model: str
    # or why the map stopped early ("interrupted (SIGINT)", ...): its missing cells are "not computed"
    status: str = "complete"

    @property
    def complete(self) -> bool:
        return self.status == "complete"


def _classify_point(params, state0, tmax, transient, settings):
    # A module-level function so that process pools can pickle it.
    sim = simulate(params, state0, tmax, settings=settings)
    if sim.status == "diverged":
        return classify(sim)
    if not sim.success and sim.status != "sticking":
        return RegimeSummary.failed(f"simulation failed: {sim.message}", transient)
    return classify(sim, transient=transient)


def check_run_length(tmax: float, transient: float | None = None, sample_step: float = 0.02) -> float:
    """The transient (default half of ``tmax``) after a one-line error unless each simulation of a
    map can run: ``tmax`` finite and > 0, its samples within the limit, the transient in [0, tmax)."""
    if not (np.isfinite(tmax) and tmax > 0):
        raise ValueError(f"tmax (the end of each simulation) must be finite and > 0; got {tmax!r}")
    if tmax / sample_step > MAX_SAMPLES:
        raise ValueError(
            f"tmax = {tmax:g} at sample_step {sample_step:g} would keep more than the "
            f"{MAX_SAMPLES:.0e} samples allowed per simulation"
        )
    if transient is None:
        transient = 0.5 * tmax
    if not (np.isfinite(transient) and 0 <= transient < tmax):
        raise ValueError(f"transient must be in [0, tmax = {tmax:g}); got {transient!r}")
    return transient


def regime_map(params: Params, state0, sigmas, abars, *, progress=None, **options) -> RegimeMap:
    """Simulate and classify every (sigma, Abar) of the grid from ``state0``: the cells of
    :func:`submit_regime_map` (``options``: its ``tmax``, ``transient``, ``settings``, ``workers``,
    ``resume``), waited for. ``progress(done, total)`` is called as points finish.
    Interrupted (KeyboardInterrupt, or SIGTERM turned into one by the CLI), it kills its own
    workers at once and returns what it has: ``status`` says why it stopped, the points it did not
    reach are ``"not computed"``.
    """
    return submit_regime_map(params, state0, sigmas, abars, **options).result(progress)


def submit_regime_map(
    params: Params,
    state0,
    sigmas,
    abars,
    *,
    tmax: float = CLASSIFY_TMAX,
    transient: float | None = None,
    settings: SimulationSettings = SIMULATION,
    workers: Workers = LOCAL,
    resume: Resume | None = None,
) -> PendingRegimeMap:
    """The cells of :func:`regime_map` checked and submitted now, collected by the returned
    object's ``result(progress)`` (or dropped by its ``cancel()``): the executor can run them
    beside other work meanwhile (a chart's curves).

    ``settings``: the model and its integrator (:class:`~slosh_bif.simulation.settings.SimulationSettings`).
    The points run on ``workers`` (:class:`~slosh_bif.simulation.settings.Workers`: a Dask
    cluster's executor, or local processes). ``resume.done``: {(i, j): RegimeSummary} of points
    already classified (a resumed run), which are not simulated again; ``resume.keep((i, j),
    summary)`` is called as each point finishes (to store it on the way)."""
    from slosh_bif.flows.smooth.integrator import resolve_backend

    settings = settings.replace(
        backend=resolve_backend(settings.backend)
    )  # a bad name is an error here, not in every worker

    sigmas = np.asarray(sigmas, dtype=float)
    abars = np.asarray(abars, dtype=float)
    for name, grid in (("sigma", sigmas), ("Abar", abars)):
        if grid.ndim != 1 or grid.size < 1 or not np.all(np.isfinite(grid)):
            raise ValueError(f"the {name} grid must be a non-empty 1-d array of finite numbers")
    if np.any(abars < 0):
        raise ValueError(f"Abar must be >= 0 on the whole grid; got min {abars.min()}")
    transient = check_run_length(tmax, transient, settings.sample_step)
    jobs = {
        (i, j): params.replace(sigma=float(s), Abar=float(a))
        for i, a in enumerate(abars)
        for j, s in enumerate(sigmas)
    }
    params.replace(sigma=float(sigmas.max())).require_positive_stiffness()  # every cell, before any work
    resume = resume or Resume()
    done = {key: s for key, s in (resume.done or {}).items() if key in jobs and s.regime != "not computed"}
    state0 = np.asarray(state0, dtype=float)
    arguments = {key: (p, state0, tmax, transient, settings) for key, p in jobs.items()}
    cells = submit_cells(
        _classify_point, arguments, workers=workers, resume=dataclasses.replace(resume, done=done)
    )
    return PendingRegimeMap(cells, (params, sigmas, abars, float(tmax), transient, settings.model))


class PendingRegimeMap:
    """A regime map whose cells are submitted (:func:`submit_regime_map`)."""

    def __init__(self, cells, grid):
        self.cells, self.grid = cells, grid

    def result(self, progress=None) -> RegimeMap:
        """The map once every cell is classified or an interruption stopped them (``status``)."""
        params, sigmas, abars, tmax, transient, model = self.grid
        results, status = self.cells.collect(progress)
        regime = np.empty((abars.size, sigmas.size), dtype=object)
        summaries = [[None] * sigmas.size for _ in abars]
        for i in range(abars.size):
            for j in range(sigmas.size):
                summary = results.get((i, j)) or RegimeSummary.not_computed(status, transient)
                regime[i, j] = summary.regime
                summaries[i][j] = summary
        return RegimeMap(params, sigmas, abars, regime, summaries, tmax, model, status)

    def cancel(self) -> None:
        """Drop the cells not finished (local workers stopped, a cluster's tasks cancelled)."""
        self.cells.cancel()
