"""Basins of attraction of the full model (9), or of the impact model (8), at one (sigma, Abar):
which response each initial state reaches, where several coexist (stable symmetric and
asymmetric orbits, a periodic response beside strongly modulated response; Figs. 9-15 start from
one state each), and how far the cell-by-cell picture can be believed.

A plane of initial states (two of X, X', w, w'; the other two zero) is followed on the
stroboscopic map of (9) (one forcing period at a time) until its strobe settles: it moves by less
than ``SETTLE_TOL`` (relative) for ``SETTLE_PERIODS`` periods in a row on a fixed point (or on a
2-cycle), within ``tmax`` at most. A settled strobe on a fixed point is refined by Newton on the
2pi-map to the orbit it settled on (for (8): the map of its exact flow, with saltation matrices),
and orbits are told apart by their state at tau = 0 (a mirror
pair's two members are two attractors); a start that has not settled by ``tmax`` is simulated
for ``TAIL_PERIODS`` more periods and labelled by its regime, marked unsettled. No fixed
simulation time decides an outcome.

Where the early motion is chaotic, the outcome of a start depends on digits no integration keeps.
Each start is therefore also run from two perturbed copies (its first component moved by
``PERTURBATIONS`` times the plane's span): a cell whose outcome changes under either is
*uncertain*. The fraction f(eps) of uncertain cells at the two sizes gives the uncertainty
exponent alpha of f ~ eps^alpha (Grebogi, McDonald, Ott and Yorke): alpha near 1 for smooth basin
boundaries, near 0 where they are fractal and the picture at any resolution is rounding's.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.continuation import newton_solve
from slosh_bif.flows.smooth import integrator
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.output import orbit_measures as impact_measures
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem
from slosh_bif.orbits.impact.switching import is_symmetric
from slosh_bif.orbits.orbit_tools import orbit_at, orbit_measures
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import START_TOL
from slosh_bif.report.files import Resume
from slosh_bif.simulation.direct import SimulationSettings, diverged_beyond, simulate
from slosh_bif.simulation.regimes import classify
from slosh_bif.simulation.settings import LOCAL, Workers
from slosh_bif.simulation.sweep import run_cells

__all__ = [
    "STATE_NAMES",
    "BasinMap",
    "basin_map",
    "SETTLE_TOL",
    "SETTLE_PERIODS",
    "PERTURBATIONS",
    "BASIN_TMAX",
]

STATE_NAMES = ("X", "Xd", "w", "wd")
SETTLE_TOL = 1e-7  # the strobe's relative move per period (or per two) that counts as settled
SETTLE_PERIODS = 3  # ... so many periods in a row
TAIL_PERIODS = 60  # an unsettled start is simulated this much longer and its regime classified
PERTURBATIONS = (
    1e-3,
    1e-6,
)  # the perturbed copies of each start, as fractions of the plane's span along the first axis
BASIN_TMAX = 2 * math.pi * 2000  # the longest any start is followed: 2,000 forcing periods
PERIOD = 2 * math.pi
VARIANTS = {"impact": "paper", "impact-corrected": "corrected"}  # the impact models' ImpactFlow variants


@dataclasses.dataclass(frozen=True)
class BasinMap:
    """``label[i, j]``: the attractor reached from the state with ``axes[0]`` = ``first[j]`` and
    ``axes[1]`` = ``second[i]``; ``uncertain[i, j]``: whether a perturbed copy of that start
    (``PERTURBATIONS``) reached another; ``periods[i, j]``: forcing periods until its strobe
    settled (NaN: not settled by ``tmax``); ``uncertain_fraction``: {eps: the share of cells whose
    outcome changed under that perturbation}; ``attractors``: {label: description};
    ``orbits``: {label: the orbit's state at tau = 0}; ``model``: "smooth" (9), "impact" (8) or
    "impact-corrected";
    ``status``: "complete", or why the map
    stopped (missing cells are "not computed")."""

    params: Params
    axes: tuple
    first: np.ndarray
    second: np.ndarray
    label: np.ndarray
    attractors: dict
    orbits: dict
    tmax: float
    status: str = "complete"
    uncertain: np.ndarray | None = None
    periods: np.ndarray | None = None
    uncertain_fraction: dict = dataclasses.field(default_factory=dict)
    model: str = "smooth"
    transient: np.ndarray | None = None  # a start or a perturbed copy of it not settled by tmax

    def fractions(self) -> dict:
        """The share of the plane's cells per attractor, largest first."""
        names, counts = np.unique(self.label, return_counts=True)
        order = np.argsort(-counts, kind="stable")
        return {str(names[k]): float(counts[k]) / self.label.size for k in order}

    def fraction_bounds(self) -> dict:
        """{attractor: (share of cells certain to reach it, share reaching it counting the
        uncertain ones)}: the basin's share lies between them at this resolution."""
        computed = self.label.size
        certain = ~self.uncertain if self.uncertain is not None else np.ones(self.label.shape, dtype=bool)
        return {
            name: (float(np.sum((self.label == name) & certain)) / computed, share)
            for name, share in self.fractions().items()
        }

    @property
    def transient_uncertain(self) -> int:
        """Uncertain cells where the start or a perturbed copy had not settled: their labels are
        a transient's regime, so they say nothing about where basins meet."""
        if self.uncertain is None or self.transient is None:
            return 0
        return int(np.sum(self.uncertain & self.transient))

    @property
    def uncertainty_exponent(self) -> float:
        """alpha of f(eps) ~ eps^alpha from the two perturbation sizes (NaN when a fraction is 0)."""
        (e1, f1), (e2, f2) = (
            sorted(self.uncertain_fraction.items())[:2]
            if len(self.uncertain_fraction) >= 2
            else ((1, 0), (1, 0))
        )
        return float(math.log(f2 / f1) / math.log(e2 / e1)) if f1 > 0 and f2 > 0 and e1 != e2 else math.nan


class _Strobe:
    """One forcing period of (9) (the compiled or scipy integrator) or of (8) (its exact flow):
    ``step(y)`` -> (state after it or None, why not); ``orbit(y)`` -> the 2pi-orbit's state at
    tau = 0 near y by Newton, or None."""

    def __init__(self, params, backend, model):
        self.params, self.backend, self.model = params, backend, model
        if model in VARIANTS:
            self.problem = ImpactOrbitProblem(params, variant=VARIANTS[model])
            self.flow = self.problem.flow_at(params.sigma)

    def step(self, y):
        if self.model in VARIANTS:
            _, ys, _, code = self.flow.run(y, 0.0, PERIOD, stick_speed=1e-9, max_impacts=100_000)
            return (ys[:, -1], "") if code == 0 else (None, "sticking" if code == 1 else "failed")
        run = integrator.integrate(self.params, y, (0.0, PERIOD), rtol=1e-9, atol=1e-11, backend=self.backend)
        return (run.z, "") if run.success and np.all(np.isfinite(run.z)) else (None, "failed")

    def orbit(self, y):
        if self.model in VARIANTS:
            run = newton_solve(self.problem, y, self.params.sigma, tol=1e-12)
            return run.x if run.converged and self.problem.in_domain(run.x, self.params.sigma) else None
        problem = ShootingProblem(self.params, segments=4, backend=self.backend)
        orbit = orbit_at(problem, problem.initial_states(y), self.params.sigma, tol=START_TOL)
        return orbit.y0 if orbit.converged else None


def _settle(params, state0, max_periods: int, backend, model="smooth"):
    """(outcome, orbit state at tau = 0 or None, periods): the strobe of (9) (or (8)) from
    ``state0`` followed until it settles (see the module docstring). The outcome is "orbit"
    (Newton found the 2pi-orbit it settled on), "period-2", a regime with "(not settled)",
    "diverged", "sticking" ((8)'s particle comes to rest on a wall) or "failed"."""
    y, before, calm1, calm2 = np.asarray(state0, dtype=float), None, 0, 0
    bound = diverged_beyond(params)
    strobe = _Strobe(params, backend, model)
    for k in range(1, max_periods + 1):
        z, why = strobe.step(y)  # both models are 2pi-periodic: every period alike
        if z is None:
            return why, None, k
        if np.max(np.abs(z[:2])) > bound:
            return "diverged", None, k
        scale = SETTLE_TOL * (1.0 + np.linalg.norm(z))
        calm1 = calm1 + 1 if np.linalg.norm(z - y) <= scale else 0
        calm2 = calm2 + 1 if before is not None and np.linalg.norm(z - before) <= scale else 0
        before, y = y, z
        if calm1 >= SETTLE_PERIODS:
            y0 = strobe.orbit(y)
            return ("orbit", y0, k) if y0 is not None else ("periodic (no 2pi orbit found)", None, k)
        if calm2 >= SETTLE_PERIODS:
            return "period-2", None, k
    sim = simulate(
        params,
        y,
        max_periods * PERIOD + TAIL_PERIODS * PERIOD,
        t0=max_periods * PERIOD,
        settings=SimulationSettings(model=model, backend=backend),
        continued=True,  # the strobe's own state: in the corrected model's contact band, maybe
    )
    if sim.status == "diverged":
        return "diverged", None, max_periods
    if not sim.success and sim.status != "sticking":
        return "failed", None, max_periods
    return f"{classify(sim).regime} (not settled)", None, max_periods


def _basin_point(params, state0, max_periods, backend, shifts, model="smooth"):
    """The outcome of ``state0`` and of its perturbed copies ``state0 + shift`` (in a worker):
    a list of (outcome, orbit state or None, periods)."""
    return [
        _settle(params, np.asarray(state0) + np.asarray(shift), max_periods, backend, model)
        for shift in ((0.0,) * 4, *shifts)
    ]


def basin_map(
    params: Params,
    first,
    second,
    *,
    axes=("X", "w"),
    tmax: float = BASIN_TMAX,
    backend: str = "auto",
    model: str = "smooth",
    workers: Workers = LOCAL,
    resume: Resume | None = None,
    progress=None,
) -> BasinMap:
    """Follow (9) (``model="impact"``: (8); ``"impact-corrected"``: the corrected impact model)
    from every state of the grid ``first`` x ``second`` in the state components ``axes`` (the
    others zero), and from two perturbed copies of each, until
    the strobe settles or ``tmax`` (rounded up to whole forcing periods) is reached, and label
    each by the attractor it reaches (see the module docstring); points run on ``workers`` (see
    :func:`~slosh_bif.simulation.sweep.run_cells`), ``progress(done, total)`` and
    ``resume.keep((i, j), outcomes)`` as they finish. ``resume.done``: such
    results of an earlier run with the same settings, not simulated again. Interrupted, it
    returns the cells done, the rest "not computed"."""
    if len(axes) != 2 or axes[0] == axes[1] or any(a not in STATE_NAMES for a in axes):
        raise ValueError(f"axes must be two different names of {', '.join(STATE_NAMES)}; got {axes!r}")
    if model not in ("smooth", *VARIANTS):
        raise ValueError(f"model must be one of smooth, {', '.join(VARIANTS)}; got {model!r}")
    params.require_positive_stiffness()
    first, second = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    for name, grid in ((axes[0], first), (axes[1], second)):
        if grid.ndim != 1 or grid.size < 1 or not np.all(np.isfinite(grid)):
            raise ValueError(f"the {name} grid must be a non-empty 1-d array of finite numbers")
    if not (np.isfinite(tmax) and tmax > 0):
        raise ValueError(f"tmax must be finite and > 0; got {tmax!r}")
    if tmax > 1e3 * BASIN_TMAX:
        raise ValueError(
            f"tmax = {tmax:g} is more than a thousand times the default {BASIN_TMAX:g}: a start "
            "that has not settled by then will not"
        )
    backend = integrator.resolve_backend(backend)
    max_periods = max(1, math.ceil(tmax / PERIOD))
    span = float(np.ptp(first)) or 1.0
    shifts = []
    for eps in PERTURBATIONS:
        shift = np.zeros(4)
        shift[STATE_NAMES.index(axes[0])] = eps * span
        shifts.append(tuple(shift))
    jobs = {}
    for i, b in enumerate(second):
        for j, a in enumerate(first):
            state = np.zeros(4)
            state[STATE_NAMES.index(axes[0])], state[STATE_NAMES.index(axes[1])] = a, b
            jobs[(i, j)] = state
    resume = resume or Resume()
    done = {key: result for key, result in (resume.done or {}).items() if key in jobs}
    arguments = {
        key: (params, state, max_periods, backend, tuple(shifts), model) for key, state in jobs.items()
    }
    results, status = run_cells(
        _basin_point,
        arguments,
        workers=workers,
        resume=dataclasses.replace(resume, done=done),
        progress=progress,
    )
    names = _Names(params, backend, model)
    label = np.full((second.size, first.size), "not computed", dtype=object)
    uncertain = np.zeros(label.shape, dtype=bool)
    periods = np.full(label.shape, np.nan)
    transient = np.zeros(label.shape, dtype=bool)
    changed = {eps: 0 for eps in PERTURBATIONS}
    for (i, j), outcomes in sorted(results.items()):
        labels = [names.of(outcome, y0) for outcome, y0, _ in outcomes]
        label[i, j] = labels[0]
        settled = not (labels[0].endswith("(not settled)") or labels[0] in ("failed", "diverged"))
        periods[i, j] = outcomes[0][2] if settled else np.nan
        transient[i, j] = any(name.endswith("(not settled)") for name in labels)
        for eps, other in zip(PERTURBATIONS, labels[1:]):
            changed[eps] += other != labels[0]
            uncertain[i, j] |= other != labels[0]
    fraction = {eps: count / max(len(results), 1) for eps, count in changed.items()}
    return BasinMap(
        params,
        tuple(axes),
        first,
        second,
        label,
        names.attractors,
        names.orbits,
        float(max_periods * PERIOD),
        status,
        uncertain,
        periods,
        fraction,
        model,
        transient,
    )


class _Names:
    """Attractor names by what they are: "symmetric orbit, A1 = 0.825", a mirror pair's members
    "asymmetric orbit a/b, A1 = ...", "non-impacting orbit ..." (max |w| < 1); orbits told apart by
    their state at tau = 0."""

    def __init__(self, params, backend, model="smooth"):
        self.params, self.model = params, model
        self.problem = (
            ImpactOrbitProblem(params, variant=VARIANTS[model])
            if model in VARIANTS
            else ShootingProblem(params, segments=4, backend=backend)
        )
        self.orbits, self.attractors = {}, {}

    def _measures(self, y0) -> dict:
        """A1, max |w| and how far the orbit is from symmetric (0 for a symmetric one)."""
        if self.model in VARIANTS:
            m = impact_measures(self.problem, y0, self.params.sigma)
            m["symmetry_defect"] = 0.0 if is_symmetric(self.params, y0, variant=VARIANTS[self.model]) else 1.0
            # by its impacts, wherever the wall is (the corrected model's |w| = D(v) is < 1 when slow)
            m["impacting"] = len(self.problem.evaluate(y0, self.params.sigma).impacts) > 0
            return m
        return orbit_measures(
            self.problem, self.problem.initial_states(y0), self.params.sigma, points_per_2pi=128
        )

    def of(self, outcome: str, y0) -> str:
        if y0 is None:
            return outcome
        y0 = np.asarray(y0, dtype=float)
        for name, z in self.orbits.items():
            if np.linalg.norm(z - y0) <= 1e-5 * (1 + np.linalg.norm(y0)):
                return name
        m = self._measures(y0)
        kind = (
            "non-impacting"
            if not m.get("impacting", m["max_abs_w"] >= 1.0)
            else "symmetric"
            if m["symmetry_defect"] < 1e-6
            else "asymmetric"
        )
        same = sum(name.startswith(f"{kind} orbit") and f"A1 = {m['A1']:.4g}" in name for name in self.orbits)
        tag = f" {'abcdefgh'[same]}" if kind == "asymmetric" else "" if same == 0 else f" ({same + 1})"
        name = f"{kind} orbit{tag}, A1 = {m['A1']:.4g}"
        self.orbits[name] = y0
        self.attractors[name] = (
            f"{kind} 2pi-orbit, A1 = {m['A1']:.4g}, max |w| = {m['max_abs_w']:.3g}, state at tau = "
            f"0: {np.round(y0, 4).tolist()}"
        )
        return name
