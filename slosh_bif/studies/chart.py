"""The (sigma, Abar) chart of the full model (9): the curves where its periodic orbits fold (LP),
double their period (PD), lose stability to a torus (NS) or break their symmetry (BP), traced
from every such point of the orbit families (side by side on several processes), and the full
model's critical forcing read off them, beside the slow flow's Abar_b of (46).

The second parameter may be any other real field of :class:`Params` (a box ``{"sigma": (lo, hi),
"beta": (lo, hi)}``: the (sigma, beta) chart); the critical forcing and the slow flow's Abar_b then
have no meaning on the chart and are left out.

What "critical" means on each model
-----------------------------------
* Slow flow (46): Abar_b(sigma) is the least forcing with a steady state on S+ at sigma, i.e.
  with a 1:1 resonant response of the reduced model (it may be unstable).
* Full model (9): Abar_c(sigma) is the least forcing at which the boundary of the region of
  *stable* period-1 orbits with wall contact (max |w| >= 1) lies at that sigma, read off the
  curves: a curve point bounds stable orbits when every multiplier but the critical one(s) is
  inside the unit circle. It is an envelope of curves, not a sweep.

  The LP, PD and NS curves all count (a BP curve bounds the symmetric orbits, not the stable
  ones: the asymmetric pair born there can be stable).

The two differ for three reasons: (46) is an asymptotic model (eps, 1/n); its steady states can
be unstable in (9) (the stable orbit is then elsewhere, or there is none: strongly modulated
response); and a stable orbit of (9) can lose stability through a period doubling or a torus
(NS) with (46) saying nothing about it.

:func:`critical_forcing_full` asks the same at one sigma (``answer critical-forcing`` and the
bench's ``critical_forcing.csv``): every family of orbits at that sigma, continued in Abar, and
the curves through their special points in a narrow sigma box; they cross that sigma at the
special points, so the envelope there is the lowest stable-bounding one.
"""

from __future__ import annotations

import dataclasses
import os
import time

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.settings import (
    BRANCHING,
    NO_SWITCHING,
    SHOOTING,
    BranchingSettings,
    ParameterRange,
    ShootingSettings,
)
from slosh_bif.orbits.shooting import PARAMETERS
from slosh_bif.orbits.starts import start_orbit
from slosh_bif.report.files import Resume
from slosh_bif.slowflow.critical import critical_curve
from slosh_bif.studies.chart_curves import (
    CurveFailure,
    curve_starts,
    pitchforks_of,
    torus_starts,
    trace_curves,
)

__all__ = [
    "Chart",
    "ChartSettings",
    "CurveFailure",
    "bifurcation_chart",
    "check_box",
]


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
        Processes tracing curves side by side (None: every core); the result does not depend on it.
    model : str
        The slow flow whose least forcing of the upper branch is drawn beside the curves.
    """

    settle: int = 150
    seeds: int = 7
    workers: int | None = None
    model: str = "slowflow"

    def __post_init__(self):
        for name, low in (("settle", 1), ("seeds", 0)):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= low):
                raise ValueError(f"ChartSettings.{name} must be an integer >= {low}; got {value!r}")
        chart_workers(self.workers)


def bifurcation_chart(
    params: Params,
    state0,
    *,
    box: dict,
    shooting: ShootingSettings = SHOOTING,
    branching: BranchingSettings = BRANCHING,
    settings: ChartSettings | None = None,
    progress=None,
    resume: Resume | None = None,
) -> Chart:
    """Trace the family of orbits at the parameter set's Abar over sigma's range (from a
    simulation from ``state0``, switched as ``branching`` says) and the primary branch's orbits at
    ``settings.seeds`` values of sigma continued in Abar, then the LP, PD, NS and BP curve through
    each of their special points (each curve once) in ``box``, ``{"sigma": (lo, hi), "Abar": (lo, hi)}``,
    on ``settings.workers`` processes (:class:`ChartSettings`), every orbit computed with ``shooting``.
    Interrupted while
    tracing curves, it returns those finished, ``status`` saying so. ``resume``: its ``done``,
    {start index: curve} of an earlier run with the same settings (which finds the same starts in
    the same order), and ``keep(i, curve)``, called as each curve finishes.

    The box's second name is the chart's second parameter: Abar, or any real field of
    :class:`Params` but sigma (the seeds are then continued in it, and there is no slow-flow
    critical curve). ``settings.model``: the slow flow whose Abar_b is drawn beside the curves."""
    if not (isinstance(box, dict) and len(box) == 2 and next(iter(box)) == "sigma"):
        raise ValueError(f'box must be {{"sigma": (lo, hi), NAME: (lo, hi)}}, sigma first; got {box!r}')
    (_, sigma_range), (second, abar_range) = box.items()
    check_box(params, sigma_range, abar_range, second)
    (s0, s1), (a0, a1) = sigma_range, abar_range
    box = {"sigma": (s0, s1), second: (a0, a1)}
    settings = settings or ChartSettings()
    workers = chart_workers(settings.workers)
    resume = resume or Resume()
    say = progress or (lambda message: None)
    started = time.perf_counter()
    start = start_orbit(
        params, state0, (s0, s1), settle=settings.settle, segments=shooting.segments, backend=shooting.backend
    )
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=shooting,
        branching=branching,
        progress=say,
        interval=ParameterRange(lo=s0, hi=s1),
    )
    say(f"orbit family: {len(family.branches)} branch(es), {sum(len(ob) for ob in family.branches)} points")
    pitchforks = pitchforks_of(family)
    starts = [s for ob in family.branches for s in curve_starts(ob, params, box, pitchforks, shooting)]
    # Folds and period doublings met when the forcing falls: the primary branch's orbits at
    # ``seeds`` values of sigma, each continued in Abar (the second parameter) over the box.
    primary = family.branches[0]
    # Seed orbits are regular points: an orbit at a pitchfork continued in Abar shows its mirror
    # pair's meeting as spurious folds.
    regular = np.ones(len(primary.branch), dtype=bool)
    for sp in primary.branch.special:
        regular[max(sp.index - 2, 0) : sp.index + 3] = False
    for sigma in np.linspace(s0, s1, settings.seeds + 2)[1:-1]:
        i = int(np.argmin(np.where(regular, np.abs(primary.branch.p - sigma), np.inf)))
        at = params.replace(sigma=float(primary.branch.p[i]))
        if not a0 <= getattr(at, second) <= a1:
            continue
        try:
            down = trace_orbits(
                at,
                primary.branch.x[i, :4],
                shooting=shooting,
                branching=NO_SWITCHING,
                progress=say,
                interval=ParameterRange(name=second, lo=a0, hi=a1),
            )
        except (ConvergenceError, ValueError) as err:
            say(f"no {second} branch at sigma = {at.sigma:.4g}: {err}")
            continue
        starts += curve_starts(down.branches[0], at, box, shooting=shooting)
    say(f"{len(starts)} special points to start curves from, on {workers} process(es)")
    if resume.done:
        say(f"{len(resume.done)} curves from an earlier run")
    curves, status, failures = trace_curves(starts, say, workers, resume.done, resume.keep)
    met = list(torus_starts(curves, params, box, shooting)) if status == "complete" else []
    if met:  # one more round, not stored for a resume (it is found again from the curves)
        say(f"{len(met)} NS curves met by the fold and period-doubling curves, not yet traced")
        tori, status, more = trace_curves(met, say, workers)
        curves, failures = curves + tori, failures + more
    slow = None
    if second == "Abar":
        try:
            slow = critical_curve(params, s0, s1, model=settings.model)
        except (RuntimeError, ValueError) as err:
            say(f"no slow-flow critical curve: {err}")
    return Chart(
        params,
        (s0, s1),
        (a0, a1),
        family,
        curves,
        slow,
        time.perf_counter() - started,
        status,
        second,
        failures,
    )


def check_box(params: Params, sigma_range, second_range, second: str = "Abar"):
    """One line before any work unless ``second`` is a real field other than sigma, the box is
    not empty, both ends of the second range are admissible values (Abar >= 0, eps > 0, a real
    restitution coefficient, ...) and the parameter set lies inside the box."""
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
            "outside the box"
        )


def chart_workers(workers) -> int:
    """The number of processes tracing curves: ``workers``, or every core for None."""
    if workers is None:
        return os.cpu_count() or 1
    if not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers must be an integer >= 1; got {workers!r}")
    return workers
