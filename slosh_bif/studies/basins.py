"""Basins of attraction of the full model (9) at one (sigma, Abar): which response each initial
state reaches, where several coexist (stable symmetric and asymmetric orbits, a periodic response
beside strongly modulated response; Figs. 9-15 start from one state each).

A plane of initial states (two of X, X', w, w'; the other two zero) is simulated with (9) and
each run classified (:func:`~slosh_bif.simulation.regimes.classify`). Where the response is
periodic, Newton on the 2pi-map from the run's last strobe finds the orbit it settled on, and
orbits are told apart by their state at tau = 0 (a mirror pair's two members are two
attractors), so each stable orbit gets its own basin; other responses are labelled by regime.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.model.params import Params
from slosh_bif.model.presets import CLASSIFY_TMAX
from slosh_bif.orbits.shooting import ShootingProblem, orbit_at, orbit_measures
from slosh_bif.orbits.starts import START_TOL
from slosh_bif.simulation.direct import MAX_SAMPLES, simulate
from slosh_bif.simulation.integrator import resolve_backend
from slosh_bif.simulation.regimes import classify
from slosh_bif.simulation.sweep import run_cells

SAMPLE_STEP = 0.02  # the simulations' sampling (simulate's default), which bounds tmax by the samples kept

__all__ = ["STATE_NAMES", "BasinMap", "basin_map"]

STATE_NAMES = ("X", "Xd", "w", "wd")


@dataclasses.dataclass(frozen=True)
class BasinMap:
    """``label[i, j]``: the attractor reached from the state with ``axes[0]`` = ``first[j]`` and
    ``axes[1]`` = ``second[i]``; ``attractors``: {label: description} (for an orbit its kind, A1
    and state at tau = 0); ``orbits``: {label: the orbit's state at tau = 0}; ``status``:
    "complete", or why the map stopped (missing cells are "not computed")."""

    params: Params
    axes: tuple
    first: np.ndarray
    second: np.ndarray
    label: np.ndarray
    attractors: dict
    orbits: dict
    tmax: float
    status: str = "complete"

    def fractions(self) -> dict:
        """The share of the plane's cells per attractor, largest first."""
        names, counts = np.unique(self.label, return_counts=True)
        order = np.argsort(-counts, kind="stable")
        return {str(names[k]): float(counts[k]) / self.label.size for k in order}


def _basin_point(params, state0, tmax, backend):
    """(regime, orbit state at tau = 0 or None) from one initial state (in a worker)."""
    sim = simulate(params, state0, tmax, sample_step=SAMPLE_STEP, backend=backend)
    if not sim.success and sim.status != "sticking":
        return "failed", None
    regime = classify(sim).regime
    if not regime.startswith("periodic"):
        return regime, None
    problem = ShootingProblem(params, segments=4, backend=backend)
    orbit = orbit_at(problem, problem.initial_states(sim.y[:, -1]), params.sigma, tol=START_TOL)  # tmax is a whole number of periods
    return regime, (orbit.y0 if orbit.converged else None)


def basin_map(
    params: Params, first, second, *, axes=("X", "w"), tmax: float = CLASSIFY_TMAX, backend: str = "auto", max_workers: int | None = None, progress=None,
    executor=None, done=None, on_result=None,
) -> BasinMap:
    """Simulate (9) from every state of the grid ``first`` x ``second`` in the state components
    ``axes`` (the others zero) to ``tmax`` (rounded up to whole forcing periods) and label each by
    the attractor it reaches; points run through ``executor`` (by default on ``max_workers``
    local processes; see :func:`~slosh_bif.simulation.sweep.run_cells`), ``progress(done, total)``
    and ``on_result((i, j), (regime, orbit state or None))`` as they finish. ``done``: such
    results of an earlier run with the same settings, not simulated again. Interrupted, it
    returns the cells done, the rest "not computed"."""
    if len(axes) != 2 or axes[0] == axes[1] or any(a not in STATE_NAMES for a in axes):
        raise ValueError(f"axes must be two different names of {', '.join(STATE_NAMES)}; got {axes!r}")
    params.require_positive_stiffness()
    first, second = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    for name, grid in ((axes[0], first), (axes[1], second)):
        if grid.ndim != 1 or grid.size < 1 or not np.all(np.isfinite(grid)):
            raise ValueError(f"the {name} grid must be a non-empty 1-d array of finite numbers")
    if not (np.isfinite(tmax) and tmax > 0):
        raise ValueError(f"tmax must be finite and > 0; got {tmax!r}")
    if tmax / SAMPLE_STEP > MAX_SAMPLES:
        raise ValueError(f"tmax = {tmax:g} would keep more than the {MAX_SAMPLES:.0e} samples allowed per simulation (one every {SAMPLE_STEP:g})")
    backend = resolve_backend(backend)
    tmax = 2 * np.pi * math.ceil(tmax / (2 * np.pi))
    jobs = {}
    for i, b in enumerate(second):
        for j, a in enumerate(first):
            state = np.zeros(4)
            state[STATE_NAMES.index(axes[0])], state[STATE_NAMES.index(axes[1])] = a, b
            jobs[(i, j)] = state
    done = {key: result for key, result in (done or {}).items() if key in jobs}
    arguments = {key: (params, state, tmax, backend) for key, state in jobs.items()}
    results, status = run_cells(_basin_point, arguments, executor=executor, max_workers=max_workers, progress=progress, done=done, on_result=on_result)
    label, attractors, orbits = _label(params, results, second.size, first.size, backend)
    return BasinMap(params, tuple(axes), first, second, label, attractors, orbits, float(tmax), status)


def _label(params, results, rows, cols, backend):
    """Cell labels: "orbit k" for the k-th distinct 2pi-orbit reached (by state at tau = 0), the
    regime otherwise; and a description of each orbit."""
    label = np.full((rows, cols), "not computed", dtype=object)
    orbits = []  # state at tau = 0 of each distinct orbit
    problem = ShootingProblem(params, segments=4, backend=backend)
    attractors = {}
    for (i, j), (regime, y0) in sorted(results.items()):
        if y0 is None:
            label[i, j] = regime if regime != "periodic-resonant" else "periodic (no 2pi orbit found)"
            continue
        k = next((k for k, z in enumerate(orbits) if np.linalg.norm(z - y0) <= 1e-5 * (1 + np.linalg.norm(y0))), None)
        if k is None:
            orbits.append(y0)
            k = len(orbits) - 1
            m = orbit_measures(problem, problem.initial_states(y0), params.sigma, points_per_2pi=128)
            kind = "symmetric" if m["symmetry_defect"] < 1e-6 else "asymmetric"
            attractors[f"orbit {k + 1}"] = f"{kind} 2pi-orbit, A1 = {m['A1']:.4g}, max |w| = {m['max_abs_w']:.3g}, state at tau = 0: {np.round(y0, 4).tolist()}"
        label[i, j] = f"orbit {k + 1}"
    return label, attractors, {f"orbit {k + 1}": y0 for k, y0 in enumerate(orbits)}
